#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "charts/draw_internal.h"
#include "io/atomic_file.h"
#include "io/input_error.h"
#include "io/text_util.h"

namespace clothfit {
namespace chart_internal {

cv::Scalar PaletteColour(size_t i) {
  static const cv::Scalar kPalette[] = {
      {180, 119, 31}, {14, 127, 255},  {44, 160, 44}, {189, 103, 148},
      {75, 86, 140},  {194, 119, 227}, {34, 189, 188}};
  return kPalette[i % (sizeof(kPalette) / sizeof(kPalette[0]))];
}

cv::Scalar ToScalar(const Rgb8& c) { return cv::Scalar(c[2], c[1], c[0]); }

void Text(cv::Mat* image, const std::string& text, cv::Point at, double scale,
          const cv::Scalar& colour) {
  cv::putText(*image, text, at, kFont, scale, colour, 1, cv::LINE_AA);
}

int TextWidth(const std::string& text, double scale) {
  int baseline = 0;
  return cv::getTextSize(text, kFont, scale, 1, &baseline).width;
}

void FittedText(cv::Mat* image, const std::string& text, cv::Point at,
                double scale, int max_width) {
  while (scale > 0.38 && TextWidth(text, scale) > max_width) scale -= 0.03;
  std::string shown = text;
  while (shown.size() > 8 && TextWidth(shown, scale) > max_width) {
    const size_t middle = shown.size() / 2;
    shown = shown.substr(0, middle - 3) + "..." + shown.substr(middle + 2);
  }
  Text(image, shown, at, scale);
}

void CentredText(cv::Mat* image, const std::string& text, int centre_x, int y,
                 double scale, const cv::Scalar& colour) {
  Text(image, text, {centre_x - TextWidth(text, scale) / 2, y}, scale, colour);
}

void RightText(cv::Mat* image, const std::string& text, int right_x,
               int centre_y, double scale) {
  Text(image, text, {right_x - TextWidth(text, scale), centre_y + 4}, scale);
}

void VerticalText(cv::Mat* image, const std::string& text, int x, int centre_y,
                  double scale) {
  int baseline = 0;
  const cv::Size size = cv::getTextSize(text, kFont, scale, 1, &baseline);
  cv::Mat strip(size.height + baseline + 4, size.width + 4, CV_8UC3,
                cv::Scalar(255, 255, 255));
  cv::putText(strip, text, {2, size.height + 2}, kFont, scale, kBlack, 1,
              cv::LINE_AA);
  cv::Mat turned;
  cv::rotate(strip, turned, cv::ROTATE_90_COUNTERCLOCKWISE);
  const int top = std::max(0, centre_y - turned.rows / 2);
  const int rows = std::min(turned.rows, image->rows - top);
  const int cols = std::min(turned.cols, image->cols - x);
  if (rows <= 0 || cols <= 0) return;
  turned(cv::Rect(0, 0, cols, rows))
      .copyTo((*image)(cv::Rect(x, top, cols, rows)));
}

std::string Format(double v) { return text_util::FormatNumber(v, 6); }

double Axis::Unit(double v) const { return log ? std::log10(v) : v; }
bool Axis::Valid(double v) const {
  return std::isfinite(v) && (!log || v > 0.0);
}
int Axis::Pixel(double v) const {
  const double u = (Unit(v) - low) / (high - low);
  return static_cast<int>(std::lround(from + u * (to - from)));
}

std::vector<double> Axis::Ticks() const {
  std::vector<double> ticks;
  if (log) {
    const int a = static_cast<int>(std::floor(low)),
              b = static_cast<int>(std::ceil(high));
    // The sparsest mantissas that give at least 3 labels, at most ~10.
    const std::vector<std::vector<double>> sets = {
        {1}, {1, 2, 5}, {1, 2, 3, 4, 5, 6, 7, 8, 9}};
    for (const std::vector<double>& mantissas : sets) {
      ticks.clear();
      for (int e = a; e <= b; ++e) {
        for (double m : mantissas) {
          const double v = m * std::pow(10.0, e);
          if (Unit(v) >= low - 1e-9 && Unit(v) <= high + 1e-9) {
            ticks.push_back(v);
          }
        }
      }
      if (ticks.size() >= 3 && ticks.size() <= 12) return ticks;
      if (ticks.size() > 12) {  // many decades: every other one
        std::vector<double> thinned;
        for (size_t i = 0; i < ticks.size(); i += (ticks.size() + 9) / 10) {
          thinned.push_back(ticks[i]);
        }
        return thinned;
      }
    }
    Axis linear;  // inside a decade: linear ticks in data units
    linear.low = std::pow(10.0, low);
    linear.high = std::pow(10.0, high);
    return linear.Ticks();
  }
  const double span = high - low;
  const double raw = span / 6.0;
  const double base = std::pow(10.0, std::floor(std::log10(raw)));
  double step = base;
  for (double m : {1.0, 2.0, 5.0, 10.0}) {
    if (m * base >= raw) {
      step = m * base;
      break;
    }
  }
  for (double v = std::ceil(low / step) * step; v <= high + 1e-9 * span;
       v += step) {
    ticks.push_back(std::abs(v) < 1e-12 * span ? 0.0 : v);
  }
  return ticks;
}

void FitAxis(const std::vector<double>& values, Axis* axis) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (double v : values) {
    if (!axis->Valid(v)) continue;
    lo = std::min(lo, axis->Unit(v));
    hi = std::max(hi, axis->Unit(v));
  }
  if (!(lo <= hi)) {
    lo = 0.0;
    hi = 1.0;
  }
  if (hi - lo < 1e-12) {
    const double pad = axis->log ? 0.5 : std::max(std::abs(lo) * 0.1, 0.5);
    lo -= pad;
    hi += pad;
  }
  const double pad = 0.06 * (hi - lo);
  axis->low = lo - pad;
  axis->high = hi + pad;
  if (!axis->log && lo >= 0.0 && axis->low < 0.0) axis->low = 0.0;
}

cv::Scalar ViridisColour(double u) {
  if (!std::isfinite(u)) return cv::Scalar(200, 200, 200);
  static const cv::Mat lut = [] {
    cv::Mat gradient(1, 256, CV_8UC1), out;
    for (int i = 0; i < 256; ++i) gradient.at<unsigned char>(0, i) = i;
    cv::applyColorMap(gradient, out, cv::COLORMAP_VIRIDIS);
    return out;
  }();
  const int i = static_cast<int>(std::lround(255 * std::clamp(u, 0.0, 1.0)));
  const cv::Vec3b c = lut.at<cv::Vec3b>(0, i);
  return cv::Scalar(c[0], c[1], c[2]);
}

std::string EncodePng(const cv::Mat& image, const std::string& path) {
  std::vector<unsigned char> bytes;
  // Charts are flat colours: the strongest deflate (level 9) halves them.
  if (!cv::imencode(".png", image, bytes, {cv::IMWRITE_PNG_COMPRESSION, 9})) {
    throw InputError(path + ": cannot encode the PNG");
  }
  return std::string(bytes.begin(), bytes.end());
}

void WritePng(const cv::Mat& image, const std::string& path) {
  WriteFileAtomically(path, EncodePng(image, path));
}

}  // namespace chart_internal
}  // namespace clothfit
