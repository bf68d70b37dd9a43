#include "charts/chart_png.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "io/atomic_file.h"
#include "io/input_error.h"

namespace clothfit {
namespace {

const cv::Scalar kBlack(0, 0, 0);
const cv::Scalar kGrey(200, 200, 200);
const cv::Scalar kWhite(255, 255, 255);
constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;

cv::Scalar Bgr(const Rgb8& c) { return cv::Scalar(c[2], c[1], c[0]); }

// Text with its left end (align 0), centre (1) or right end (2) at x.
void Text(cv::Mat* image, const std::string& text, int x, int y, double scale,
          int align = 0, const cv::Scalar& color = kBlack) {
  int baseline = 0;
  const cv::Size size = cv::getTextSize(text, kFont, scale, 1, &baseline);
  x -= align * size.width / 2;
  cv::putText(*image, text, cv::Point(x, y), kFont, scale, color, 1,
              cv::LINE_AA);
}

std::string Format(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.3g", value);
  return buffer;
}

// A "nice" tick step giving about `count` ticks over span.
double TickStep(double span, int count) {
  const double raw = span / count;
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 2.5, 5.0, 10.0}) {
    if (m * power >= raw) return m * power;
  }
  return 10.0 * power;
}

void Save(const cv::Mat& image, const std::string& path) {
  std::vector<uchar> bytes;
  if (!cv::imencode(".png", image, bytes)) {
    throw InputError(path + ": cannot write: PNG encoding failed");
  }
  WriteFileAtomically(path, std::string(bytes.begin(), bytes.end()));
}

// lo/hi from the data when lo >= hi; widened when flat.
void Range(double* lo, double* hi, double data_lo, double data_hi) {
  if (*lo < *hi) return;
  *lo = data_lo;
  *hi = data_hi;
  if (!(*hi > *lo)) {
    *lo -= 0.5;
    *hi += 0.5;
  }
}

}  // namespace

void WriteLineChartPng(const LineChart& chart, const std::string& path) {
  double x_lo = HUGE_VAL, x_hi = -HUGE_VAL, y_lo = HUGE_VAL, y_hi = -HUGE_VAL;
  for (const ChartSeries& s : chart.series) {
    if (s.x.size() != s.y.size()) {
      throw InputError(path + ": chart series '" + s.name +
                       "' has different x and y counts");
    }
    for (size_t i = 0; i < s.x.size(); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      x_lo = std::min(x_lo, s.x[i]);
      x_hi = std::max(x_hi, s.x[i]);
      y_lo = std::min(y_lo, s.y[i]);
      y_hi = std::max(y_hi, s.y[i]);
    }
  }
  if (x_lo > x_hi) throw InputError(path + ": chart has no finite points");
  double x_min = chart.x_min, x_max = chart.x_max;
  double y_min = chart.y_min, y_max = chart.y_max;
  Range(&x_min, &x_max, x_lo, x_hi);
  Range(&y_min, &y_max, y_lo, y_hi);

  cv::Mat image(chart.height, chart.width, CV_8UC3, kWhite);
  const int left = 80, right = 200, top = 50, bottom = 60;
  const int plot_w = chart.width - left - right;
  const int plot_h = chart.height - top - bottom;
  auto px = [&](double x) {
    return left + static_cast<int>(
                      std::lround((x - x_min) / (x_max - x_min) * plot_w));
  };
  auto py = [&](double y) {
    return top + plot_h -
           static_cast<int>(
               std::lround((y - y_min) / (y_max - y_min) * plot_h));
  };
  // Grid and ticks.
  const double x_step = TickStep(x_max - x_min, 8);
  for (double x = std::ceil(x_min / x_step) * x_step;
       x <= x_max + 1e-9 * x_step; x += x_step) {
    cv::line(image, {px(x), top}, {px(x), top + plot_h}, kGrey, 1);
    Text(&image, Format(x), px(x), top + plot_h + 18, 0.45, 1);
  }
  const double y_step = TickStep(y_max - y_min, 6);
  for (double y = std::ceil(y_min / y_step) * y_step;
       y <= y_max + 1e-9 * y_step; y += y_step) {
    cv::line(image, {left, py(y)}, {left + plot_w, py(y)}, kGrey, 1);
    Text(&image, Format(y), left - 8, py(y) + 5, 0.45, 2);
  }
  cv::rectangle(image, {left, top}, {left + plot_w, top + plot_h}, kBlack, 1);
  Text(&image, chart.title, left + plot_w / 2, 30, 0.6, 1);
  Text(&image, chart.x_label, left + plot_w / 2, chart.height - 15, 0.5, 1);
  // The y label, rotated: drawn on its side into a strip, then turned.
  {
    int baseline = 0;
    const cv::Size size =
        cv::getTextSize(chart.y_label, kFont, 0.5, 1, &baseline);
    cv::Mat strip(size.height + 10, std::max(size.width + 10, 1), CV_8UC3,
                  kWhite);
    Text(&strip, chart.y_label, 5, size.height + 3, 0.5);
    cv::Mat turned;
    cv::rotate(strip, turned, cv::ROTATE_90_COUNTERCLOCKWISE);
    const int x0 = 8;
    const int y0 = std::max(0, top + plot_h / 2 - turned.rows / 2);
    if (y0 + turned.rows <= image.rows && x0 + turned.cols <= image.cols) {
      turned.copyTo(image(cv::Rect(x0, y0, turned.cols, turned.rows)));
    }
  }
  // Series, clipped to the plot, and the legend.
  const cv::Rect plot(left, top, plot_w + 1, plot_h + 1);
  int legend_y = top + 10;
  for (const ChartSeries& s : chart.series) {
    const cv::Scalar color = Bgr(s.color);
    cv::Mat layer = image(plot);
    for (size_t i = 0; i + 1 < s.x.size(); ++i) {
      if (s.dashed && i % 2 == 1) continue;
      const cv::Point a(px(s.x[i]) - left, py(s.y[i]) - top);
      const cv::Point b(px(s.x[i + 1]) - left, py(s.y[i + 1]) - top);
      cv::line(layer, a, b, color, 2, cv::LINE_AA);
    }
    if (s.markers) {
      for (size_t i = 0; i < s.x.size(); ++i) {
        cv::circle(layer, {px(s.x[i]) - left, py(s.y[i]) - top}, 3, color,
                   cv::FILLED, cv::LINE_AA);
      }
    }
    const int lx = left + plot_w + 15;
    cv::line(image, {lx, legend_y}, {lx + 30, legend_y}, color, 2, cv::LINE_AA);
    if (s.markers) cv::circle(image, {lx + 15, legend_y}, 3, color, cv::FILLED);
    Text(&image, s.name, lx + 38, legend_y + 5, 0.45);
    legend_y += 24;
  }
  Save(image, path);
}

}  // namespace clothfit
