// Heat-map charts as PNG, drawn with OpenCV: a grid of coloured cells
// (viridis, linear or logarithmic scale) with the value printed in each
// cell, labelled axes, a title, a colour bar, and an outline around cells
// above a threshold. The data behind a chart are written by its caller
// (CSV); this draws only.
#pragma once

#include <string>
#include <vector>

namespace clothfit {

struct HeatMap {
  std::string title;
  std::string x_title, y_title;
  std::vector<std::string> x_labels;  // one per column, left to right
  std::vector<std::string> y_labels;  // one per row, top to bottom
  // values[row * columns + column]; non-finite values are drawn grey.
  std::vector<double> values;
  std::vector<std::string> cell_text;  // optional, same layout as values
  double lo = 0.0, hi = 1.0;           // colour range (clamped outside)
  bool log_scale = false;              // colours by log10 (lo, hi > 0)
  std::string legend;                  // colour bar caption
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
