// Line charts as PNG images drawn with OpenCV (several series over one x
// axis; heat maps: charts/heat_map.h). Written atomically
// (io/atomic_file.h); the CSV behind a chart is the caller's to write.
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

// Throws InputError naming the path when it cannot be written, and for an
// empty or inconsistent chart.
void WriteLineChartPng(const LineChart& chart, const std::string& path);

}  // namespace clothfit
