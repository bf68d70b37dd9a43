// Images as charts (PNG, drawn with OpenCV in image_chart.cc): a scalar
// field over a rectangle of two quantities in viridis colours with
// labelled axes and a colour bar (e.g. a BRDF over theta_h and theta_d),
// and a picture (8-bit sRGB pixels) with a title and a caption (e.g. a lit
// sphere). Written atomically (io/atomic_file.h).
#pragma once

#include <string>
#include <vector>

#include "charts/chart.h"

namespace clothfit {

struct ImageChart {
  std::string title, x_label, y_label, colour_label;
  int columns = 0, rows = 0;
  // values[row * columns + column]; row 0 at y_high (the top), column 0 at
  // x_low. Non-finite values are drawn grey.
  std::vector<double> values;
  // The extent: the outer edges of the cells, in axis units.
  double x_low = 0.0, x_high = 1.0, y_low = 0.0, y_high = 1.0;
  bool log_colour = false;  // colours by log10 (positive values only)
  std::string note;         // one line under the axes
  int cell_pixels = 4;
};

// Throws InputError when values do not match columns x rows or the file
// cannot be written.
void WriteImageChartPng(const ImageChart& chart, const std::string& path);

struct Picture {
  std::string title;
  std::vector<std::string> caption;  // lines under the picture
  int width = 0, height = 0;
  std::vector<Rgb8> pixels;  // row-major, row 0 at the top, sRGB
};

void WritePicturePng(const Picture& picture, const std::string& path);

}  // namespace clothfit
