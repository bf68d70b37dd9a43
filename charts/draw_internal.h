// What the chart drawers of charts/ share (OpenCV; included by their .cc
// files only): colours, text, axes with ticks, PNG output.
#pragma once

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "charts/chart.h"

namespace clothfit {
namespace chart_internal {

inline const cv::Scalar kBlack(0, 0, 0), kGrey(170, 170, 170),
    kLight(235, 235, 235), kRed(30, 30, 220), kFrontColour(60, 60, 60);
inline constexpr int kFont = 0;  // cv::FONT_HERSHEY_SIMPLEX

// Series colours (BGR): blue, orange, green, purple, brown, pink, olive.
cv::Scalar PaletteColour(size_t i);
cv::Scalar ToScalar(const Rgb8& rgb);

void Text(cv::Mat* image, const std::string& text, cv::Point at,
          double scale = 0.45, const cv::Scalar& colour = kBlack);
// Text whose box is centred horizontally at `centre_x` (baseline y).
void CentredText(cv::Mat* image, const std::string& text, int centre_x, int y,
                 double scale = 0.45, const cv::Scalar& colour = kBlack);
// Text ending at `right_x`, vertically centred at `centre_y`.
void RightText(cv::Mat* image, const std::string& text, int right_x,
               int centre_y, double scale = 0.4);
// Text turned 90 degrees counter-clockwise (reading upwards), centred at
// (`x`, `centre_y`); `x` is the left edge of its column.
void VerticalText(cv::Mat* image, const std::string& text, int x, int centre_y,
                  double scale = 0.5);
int TextWidth(const std::string& text, double scale);
// Text at `at` in at most `max_width` pixels: a smaller scale (down to
// 0.38), then the middle left out ("...").
void FittedText(cv::Mat* image, const std::string& text, cv::Point at,
                double scale, int max_width);

std::string Format(double v);

// One axis: data range to pixels, linear or log10.
struct Axis {
  bool log = false;
  double low = 0.0, high = 1.0;  // in axis units (log10 for log axes)
  int from = 0, to = 1;          // pixels

  double Unit(double v) const;
  bool Valid(double v) const;
  int Pixel(double v) const;
  // Tick values (data units): on a log axis the decades, with 2 and 5 (or
  // every integer mantissa) where they give a few labels; linear ticks
  // inside one decade.
  std::vector<double> Ticks() const;
};

// Range of the valid values, padded; a single value gets a unit range.
void FitAxis(const std::vector<double>& values, Axis* axis);

// The viridis colour of u in [0, 1] (clamped; NaN: grey).
cv::Scalar ViridisColour(double u);

std::string EncodePng(const cv::Mat& image, const std::string& path);
void WritePng(const cv::Mat& image, const std::string& path);

}  // namespace chart_internal
}  // namespace clothfit
