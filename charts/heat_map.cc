#include "charts/heat_map.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "charts/draw_internal.h"
#include "io/input_error.h"
#include "io/text_util.h"

namespace clothfit {
namespace {

constexpr int kCellWidth = 84;
constexpr int kCellHeight = 40;
constexpr int kLeft = 120;      // room for the row labels and y title
constexpr int kGap = 40;        // between panels
constexpr int kTop = 70;        // title
constexpr int kBottom = 90;     // column labels, x title, threshold note
constexpr int kBarWidth = 150;  // colour bar and its labels
constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;
const cv::Scalar kInk(30, 30, 30);
const cv::Scalar kPaper(255, 255, 255);
const cv::Scalar kMissing(190, 190, 190);
const cv::Scalar kAlarm(0, 0, 230);  // BGR red

// Position of a value in [0, 1] on the colour scale [lo, hi].
double Position(const HeatMap& map, double lo, double hi, double value) {
  double v = value;
  if (map.log_scale) {
    lo = std::log10(lo);
    hi = std::log10(hi);
    v = std::log10(std::max(value, 1e-300));
  }
  if (!(hi > lo)) return 0.5;
  return std::clamp((v - lo) / (hi - lo), 0.0, 1.0);
}

// Text centred on (x, y) in ink or paper, whichever reads better on `under`.
void Centred(cv::Mat* img, const std::string& text, int x, int y, double scale,
             const cv::Scalar& under) {
  int baseline = 0;
  const cv::Size size = cv::getTextSize(text, kFont, scale, 1, &baseline);
  const double luma = 0.114 * under[0] + 0.587 * under[1] + 0.299 * under[2];
  cv::putText(*img, text, cv::Point(x - size.width / 2, y + size.height / 2),
              kFont, scale, luma > 128 ? kInk : kPaper, 1, cv::LINE_AA);
}

// The colour range: map.lo, map.hi, or where lo >= hi the finite values'
// (positive ones on a log scale), widened when flat.
void ColourRange(const HeatMap& map, double* lo, double* hi) {
  *lo = map.lo;
  *hi = map.hi;
  if (*lo < *hi) return;
  *lo = HUGE_VAL;
  *hi = -HUGE_VAL;
  for (const HeatMapPanel& p : map.panels) {
    for (double v : p.values) {
      if (!std::isfinite(v) || (map.log_scale && !(v > 0.0))) continue;
      *lo = std::min(*lo, v);
      *hi = std::max(*hi, v);
    }
  }
  if (*lo > *hi) {  // nothing drawable
    *lo = map.log_scale ? 0.1 : 0.0;
    *hi = 1.0;
  } else if (*lo == *hi) {
    *lo = map.log_scale ? *lo / 2.0 : *lo - 0.5;
    *hi = map.log_scale ? *hi * 2.0 : *hi + 0.5;
  }
}

std::string Format(double value, const std::string& unit) {
  return std::isfinite(value) ? text_util::FormatNumber(value, 3) + unit : "-";
}

}  // namespace

void WriteHeatMapPng(const HeatMap& map, const std::string& path) {
  const int cols = static_cast<int>(map.x_labels.size());
  const int rows = static_cast<int>(map.y_labels.size());
  bool consistent = cols > 0 && rows > 0 && !map.panels.empty();
  for (const HeatMapPanel& p : map.panels) {
    consistent = consistent &&
                 p.values.size() == static_cast<size_t>(cols * rows) &&
                 (p.cell_text.empty() || p.cell_text.size() == p.values.size());
  }
  if (!consistent) {
    throw InputError(path + ": heat map: labels and values do not match");
  }
  if (map.log_scale && map.lo < map.hi && !(map.lo > 0.0)) {
    throw InputError(path + ": heat map: a log scale needs lo, hi > 0");
  }
  double lo = 0.0, hi = 1.0;
  ColourRange(map, &lo, &hi);

  const int n = static_cast<int>(map.panels.size());
  const int panel_w = cols * kCellWidth;
  const int grid_w = n * panel_w + (n - 1) * kGap;
  int baseline = 0;
  // Wide enough for the title and for the colour bar's caption, which
  // starts 10 pixels left of the bar (20 right of the grid).
  const int width = std::max(
      {kLeft + grid_w + kBarWidth,
       cv::getTextSize(map.title, kFont, 0.6, 1, &baseline).width + 24,
       kLeft + grid_w + 10 +
           cv::getTextSize(map.legend, kFont, 0.4, 1, &baseline).width + 12});
  const int height = kTop + rows * kCellHeight + kBottom;
  cv::Mat img(height, width, CV_8UC3, kPaper);
  cv::putText(img, map.title, cv::Point(12, 30), kFont, 0.6, kInk, 1,
              cv::LINE_AA);
  const int grid_bottom = kTop + rows * kCellHeight;
  for (int k = 0; k < n; ++k) {
    const HeatMapPanel& panel = map.panels[k];
    const int x0 = kLeft + k * (panel_w + kGap);
    if (!panel.title.empty()) {
      Centred(&img, panel.title, x0 + panel_w / 2, kTop - 12, 0.45, kPaper);
    }
    for (int r = 0; r < rows; ++r) {
      for (int c = 0; c < cols; ++c) {
        const size_t i = static_cast<size_t>(r * cols + c);
        const double v = panel.values[i];
        const cv::Rect cell(x0 + c * kCellWidth, kTop + r * kCellHeight,
                            kCellWidth, kCellHeight);
        const cv::Scalar fill =
            std::isfinite(v)
                ? chart_internal::ViridisColour(Position(map, lo, hi, v))
                : kMissing;
        cv::rectangle(img, cell, fill, cv::FILLED);
        cv::rectangle(img, cell, kPaper, 1);
        if (map.outline_above && std::isfinite(v) && v > map.threshold) {
          cv::rectangle(
              img,
              cv::Rect(cell.x + 2, cell.y + 2, cell.width - 4, cell.height - 4),
              kAlarm, 2);
        }
        Centred(
            &img,
            panel.cell_text.empty() ? Format(v, map.unit) : panel.cell_text[i],
            cell.x + kCellWidth / 2, cell.y + kCellHeight / 2, 0.42, fill);
      }
    }
    for (int c = 0; c < cols; ++c) {
      Centred(&img, map.x_labels[c], x0 + c * kCellWidth + kCellWidth / 2,
              grid_bottom + 15, 0.45, kPaper);
    }
    Centred(&img, map.x_title, x0 + panel_w / 2, grid_bottom + 42, 0.5, kPaper);
  }
  for (int r = 0; r < rows; ++r) {
    Centred(&img, map.y_labels[r], kLeft - 35,
            kTop + r * kCellHeight + kCellHeight / 2, 0.45, kPaper);
  }
  cv::putText(img, map.y_title, cv::Point(8, kTop - 10), kFont, 0.5, kInk, 1,
              cv::LINE_AA);
  if (map.outline_above) {
    cv::putText(img, map.threshold_label, cv::Point(12, grid_bottom + 72),
                kFont, 0.45, kAlarm, 1, cv::LINE_AA);
  }

  // Colour bar: bottom = lo, top = hi, with five labelled ticks.
  const int bar_x = kLeft + grid_w + 20;
  const int bar_h = rows * kCellHeight;
  for (int y = 0; y < bar_h; ++y) {
    const double t = 1.0 - static_cast<double>(y) / std::max(1, bar_h - 1);
    cv::line(img, cv::Point(bar_x, kTop + y), cv::Point(bar_x + 20, kTop + y),
             chart_internal::ViridisColour(t));
  }
  for (int k = 0; k <= 4; ++k) {
    const double t = k / 4.0;
    const double value =
        map.log_scale
            ? std::pow(10.0,
                       std::log10(lo) + t * (std::log10(hi) - std::log10(lo)))
            : lo + t * (hi - lo);
    const int y = kTop + static_cast<int>((1.0 - t) * (bar_h - 1));
    cv::line(img, cv::Point(bar_x + 20, y), cv::Point(bar_x + 25, y), kInk);
    cv::putText(img, Format(value, map.unit), cv::Point(bar_x + 28, y + 5),
                kFont, 0.4, kInk, 1, cv::LINE_AA);
  }
  cv::putText(img, map.legend, cv::Point(bar_x - 10, kTop - 10), kFont, 0.4,
              kInk, 1, cv::LINE_AA);

  chart_internal::WritePng(img, path);
}

}  // namespace clothfit
