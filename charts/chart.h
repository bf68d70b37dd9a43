// Charts as PNG (drawn with OpenCV; OpenCV stays in chart.cc): scatter and
// line charts with optional log axes and a Pareto front, and polar plots of
// a BRDF slice. Every file is written atomically (io/atomic_file.h).
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace clothfit {

using Rgb8 = std::array<unsigned char, 3>;

struct ChartPoint {
  double x = 0.0, y = 0.0;
  std::string label;       // drawn beside the point when not empty
  bool highlight = false;  // ringed (e.g. the default configuration)
};

struct ScatterSeries {
  std::string name;  // legend
  std::vector<ChartPoint> points;
  bool lines = false;          // join the points in order
  bool dashed = false;         // ... with every other segment left out
  bool markers = true;         // a dot at every point
  int marker_radius = 4;       // pixels (2: thousands of points stay apart)
  std::optional<Rgb8> colour;  // else the palette's, by the series' index
  // Part of the Pareto front's point set (fastest at each error level).
  bool pareto = false;
};

// One drawer for scatter and line charts.
struct ScatterChart {
  std::string title, x_label, y_label;
  bool log_x = false, log_y = false;
  // A fixed y range when y_min < y_max (e.g. [0, 1] for a fraction);
  // otherwise it comes from the data. The same for x.
  double y_min = 0.0, y_max = 0.0;
  double x_min = 0.0, x_max = 0.0;
  // Horizontal reference lines (e.g. 0 for residuals, 1 for an albedo).
  std::vector<double> y_reference;
  std::string y_reference_label;  // its legend entry (empty: none)
  std::vector<ScatterSeries> series;
  // Mark the Pareto front (smallest y for every x and below) over the
  // points of the series with pareto = true.
  bool pareto = false;
  int width = 900, height = 600;
};

// The labelled ticks of an axis over [low, high] (data units, low < high;
// positive for a log axis): on a log axis the decades, or with 2 and 5, or
// every mantissa 1..9, whichever first gives 3 to 12 labels (linear ticks
// when none does); on a linear axis 1, 2 or 5 times a power of ten, about
// six of them.
std::vector<double> AxisTicks(double low, double high, bool log);

// Indices (series, point) of the Pareto-optimal points among the series
// with pareto = true: no other point has both x <= and y <= with one
// strictly smaller. Sorted by x.
std::vector<std::pair<int, int>> ParetoFront(const ScatterChart& spec);

// Throws InputError when the file cannot be written. Non-finite points (and
// non-positive ones on a log axis) are left out and counted in the title.
void WriteScatterChartPng(const ScatterChart& spec, const std::string& path);
// Several charts stacked top to bottom in one PNG (each its own axes).
void WriteScatterChartsPng(const std::vector<ScatterChart>& charts,
                           const std::string& path);

// One panel of a polar plot: a slice of a BRDF in the plane of incidence,
// angle = theta_o in degrees in [-90, 90] (negative: the side of the light),
// radius = value. The title is drawn above the panel.
struct PolarPanel {
  std::string title;
  std::vector<double> measured_angle_deg, measured_value;  // dots
  std::vector<double> model_angle_deg, model_value;        // a curve
  double incidence_deg = 0.0;                              // an arrow
};

// Panels in rows of up to four, one radial scale (the largest of the
// measured values and the 90th percentile of the model's; the curve is
// clipped at the rim beyond it), rings labelled with their value in
// `value_label`, the angle theta_o labelled every 30 degrees (polar_chart.cc).
void WritePolarPlotPng(const std::vector<PolarPanel>& panels,
                       const std::string& title, const std::string& path,
                       const std::string& value_label = "value");

}  // namespace clothfit
