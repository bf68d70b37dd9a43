// Charts as PNG images drawn with OpenCV: line charts (several series over
// one x axis) and heat maps (one or more panels over a shared colour
// scale). Written atomically (io/atomic_file.h); the CSV behind a chart is
// the caller's to write.
#pragma once

#include <array>
#include <string>
#include <vector>

namespace clothfit {

using Rgb8 = std::array<unsigned char, 3>;

struct ChartSeries {
  std::string name;
  std::vector<double> x, y;
  Rgb8 color{0, 0, 0};
  bool dashed = false;
  bool markers = false;  // a dot at every point
};

struct LineChart {
  std::string title, x_label, y_label;
  std::vector<ChartSeries> series;
  // Axis ranges; when lo >= hi they come from the data.
  double x_min = 0.0, x_max = 0.0, y_min = 0.0, y_max = 0.0;
  int width = 900, height = 560;
};

// One panel of a heat map: values[row * columns + column], row 0 drawn at
// the bottom (like a y axis).
struct HeatmapPanel {
  std::string title;
  int rows = 0, columns = 0;
  std::vector<double> values;
};

struct Heatmap {
  std::string title, x_label, y_label, value_label;
  std::vector<std::string> x_ticks, y_ticks;  // one per column / row
  std::vector<HeatmapPanel> panels;           // drawn side by side
  // Colour scale; when lo >= hi it spans the values.
  double v_min = 0.0, v_max = 0.0;
  int cell = 56;  // cell size in pixels
};

// Throws InputError naming the path when it cannot be written, and for an
// empty or inconsistent chart.
void WriteLineChartPng(const LineChart& chart, const std::string& path);
void WriteHeatmapPng(const Heatmap& heatmap, const std::string& path);

}  // namespace clothfit
