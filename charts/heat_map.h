// Heat-map charts as PNG, drawn with OpenCV: one or more panels side by
// side over shared axes and one colour scale (viridis, linear or
// logarithmic), a grid of coloured cells with a text in each (given, or the
// value), labelled axes, a title, a colour bar, and an outline around cells
// above a threshold. The data behind a chart are written by its caller
// (CSV); this draws only, atomically (io/atomic_file.h). The one heat map
// of the project: the holes' error charts (holes/hole_charts.cc) and the
// slab's error map (data_synthetic/slab_error_map.cc) use it.
#pragma once

#include <string>
#include <vector>

namespace clothfit {

struct HeatMapPanel {
  std::string title;  // above the panel; may be empty
  // values[row * columns + column], row 0 at the top (the order of
  // HeatMap::y_labels); non-finite values are drawn grey.
  std::vector<double> values;
  // Optional, same layout as values; empty: each value printed with three
  // significant digits ("-" where it is not finite).
  std::vector<std::string> cell_text;
};

struct HeatMap {
  std::string title;
  std::string x_title, y_title;
  std::vector<std::string> x_labels;  // one per column, left to right
  std::vector<std::string> y_labels;  // one per row, top to bottom
  std::vector<HeatMapPanel> panels;   // side by side, at least one
  // Colour range (clamped outside); lo >= hi: the range of the finite
  // values of all panels.
  double lo = 0.0, hi = 0.0;
  bool log_scale = false;  // colours by log10 (lo, hi > 0)
  std::string legend;      // colour bar caption
  // The values' unit, appended to the colour bar's tick labels and to the
  // cells' default text (e.g. "%": values 0.5 and 12 read "0.5%", "12%");
  // a cell_text given should use the same unit.
  std::string unit;
  // With outline_above, cells whose value exceeds `threshold` get a red
  // outline, explained by threshold_label under the grid.
  bool outline_above = false;
  double threshold = 0.0;
  std::string threshold_label;  // e.g. "red outline: error > 1 %"
};

// Draws the chart and writes it to `path` atomically. Throws InputError
// when the path cannot be written or the layout is inconsistent.
void WriteHeatMapPng(const HeatMap& map, const std::string& path);

}  // namespace clothfit
