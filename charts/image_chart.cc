#include "charts/image_chart.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "charts/draw_internal.h"
#include "io/input_error.h"

namespace clothfit {

using namespace chart_internal;  // NOLINT: the drawers' shared helpers

void WriteImageChartPng(const ImageChart& chart, const std::string& path) {
  if (chart.columns <= 0 || chart.rows <= 0 ||
      chart.values.size() != size_t(chart.columns) * chart.rows) {
    throw InputError(path + ": image chart values do not match its size");
  }
  const int left = 90, top = 45, bar = 110, bottom = 70;
  const int w = chart.columns * chart.cell_pixels,
            h = chart.rows * chart.cell_pixels;
  const int width =
      std::max(left + w + bar, left + 10 + TextWidth(chart.note, 0.4));
  cv::Mat image(top + h + bottom, width, CV_8UC3, cv::Scalar(255, 255, 255));
  // Colour range over the finite (positive, for log) values.
  Axis colour;
  colour.log = chart.log_colour;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (double v : chart.values) {
    if (!colour.Valid(v)) continue;
    lo = std::min(lo, colour.Unit(v));
    hi = std::max(hi, colour.Unit(v));
  }
  if (!(lo < hi)) {
    lo = lo <= hi ? lo - 0.5 : 0.0;
    hi = lo + 1.0;
  }
  colour.low = lo;
  colour.high = hi;
  for (int r = 0; r < chart.rows; ++r) {
    for (int c = 0; c < chart.columns; ++c) {
      const double v = chart.values[size_t(r) * chart.columns + c];
      const double u =
          colour.Valid(v) ? (colour.Unit(v) - lo) / (hi - lo) : std::nan("");
      cv::rectangle(
          image,
          cv::Rect(left + c * chart.cell_pixels, top + r * chart.cell_pixels,
                   chart.cell_pixels, chart.cell_pixels),
          ViridisColour(u), cv::FILLED);
    }
  }
  cv::rectangle(image, {left - 1, top - 1}, {left + w, top + h}, kBlack);
  Axis x, y;
  x.low = chart.x_low;
  x.high = chart.x_high;
  x.from = left;
  x.to = left + w;
  y.low = chart.y_low;
  y.high = chart.y_high;
  y.from = top + h;
  y.to = top;
  for (double t : x.Ticks()) {
    cv::line(image, {x.Pixel(t), y.from}, {x.Pixel(t), y.from + 5}, kBlack);
    CentredText(&image, Format(t), x.Pixel(t), y.from + 20, 0.4);
  }
  for (double t : y.Ticks()) {
    cv::line(image, {x.from - 5, y.Pixel(t)}, {x.from, y.Pixel(t)}, kBlack);
    RightText(&image, Format(t), x.from - 8, y.Pixel(t), 0.4);
  }
  FittedText(&image, chart.title, {left, 28}, 0.55, image.cols - left - 10);
  CentredText(&image, chart.x_label, left + w / 2, y.from + 42, 0.5);
  VerticalText(&image, chart.y_label, 4, top + h / 2, 0.5);
  if (!chart.note.empty()) {
    Text(&image, chart.note, {left, y.from + 62}, 0.4, kFrontColour);
  }
  // Colour bar with its ticks and caption.
  const int bx = left + w + 20;
  for (int j = 0; j < h; ++j) {
    const double u = 1.0 - (j + 0.5) / h;
    cv::line(image, {bx, top + j}, {bx + 14, top + j}, ViridisColour(u));
  }
  cv::rectangle(image, {bx - 1, top - 1}, {bx + 15, top + h}, kBlack);
  Axis bar_axis = colour;
  bar_axis.from = top + h;
  bar_axis.to = top;
  for (double t : bar_axis.Ticks()) {
    const int py = bar_axis.Pixel(t);
    cv::line(image, {bx + 15, py}, {bx + 19, py}, kBlack);
    Text(&image, Format(t), {bx + 22, py + 4}, 0.38);
  }
  VerticalText(&image,
               chart.colour_label + (chart.log_colour ? " (log scale)" : ""),
               bx + 72, top + h / 2, 0.45);
  WritePng(image, path);
}

void WritePicturePng(const Picture& picture, const std::string& path) {
  if (picture.pixels.size() != size_t(picture.width) * picture.height) {
    throw InputError(path + ": picture pixels do not match its size");
  }
  const int margin = 20, top = 40;
  const int lines = static_cast<int>(picture.caption.size());
  int width = picture.width + 2 * margin;
  for (const std::string& line : picture.caption) {
    width = std::max(width, TextWidth(line, 0.42) + 2 * margin);
  }
  width = std::max(width, TextWidth(picture.title, 0.55) + 2 * margin);
  cv::Mat image(top + picture.height + 12 + 20 * lines, width, CV_8UC3,
                cv::Scalar(255, 255, 255));
  const int x0 = (width - picture.width) / 2;
  for (int j = 0; j < picture.height; ++j) {
    for (int i = 0; i < picture.width; ++i) {
      const Rgb8& c = picture.pixels[size_t(j) * picture.width + i];
      image.at<cv::Vec3b>(top + j, x0 + i) = cv::Vec3b(c[2], c[1], c[0]);
    }
  }
  Text(&image, picture.title, {margin, 26}, 0.55);
  for (int k = 0; k < lines; ++k) {
    Text(&image, picture.caption[k],
         {margin, top + picture.height + 26 + 20 * k}, 0.42, kFrontColour);
  }
  WritePng(image, path);
}

}  // namespace clothfit
