#include "charts/chart.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "charts/draw_internal.h"

namespace clothfit {
namespace {

using namespace chart_internal;  // NOLINT: the drawers' shared helpers

// A series' own colour, else the palette's for index i.
cv::Scalar SeriesColour(const ScatterSeries& series, size_t i) {
  return series.colour ? ToScalar(*series.colour) : PaletteColour(i);
}

cv::Mat DrawScatterChart(const ScatterChart& spec);

}  // namespace

std::vector<double> AxisTicks(double low, double high, bool log) {
  Axis axis;
  axis.log = log;
  axis.low = axis.Unit(low);
  axis.high = axis.Unit(high);
  return axis.Ticks();
}

std::vector<std::pair<int, int>> ParetoFront(const ScatterChart& spec) {
  std::vector<std::pair<int, int>> all;
  for (size_t s = 0; s < spec.series.size(); ++s) {
    if (!spec.series[s].pareto) continue;
    for (size_t p = 0; p < spec.series[s].points.size(); ++p) {
      const ChartPoint& q = spec.series[s].points[p];
      if (std::isfinite(q.x) && std::isfinite(q.y)) {
        all.emplace_back(static_cast<int>(s), static_cast<int>(p));
      }
    }
  }
  auto at = [&](const std::pair<int, int>& i) -> const ChartPoint& {
    return spec.series[i.first].points[i.second];
  };
  std::sort(all.begin(), all.end(), [&](const auto& a, const auto& b) {
    return at(a).x < at(b).x || (at(a).x == at(b).x && at(a).y < at(b).y);
  });
  std::vector<std::pair<int, int>> front;
  double best_y = std::numeric_limits<double>::infinity();
  for (const auto& i : all) {
    if (at(i).y < best_y) {
      front.push_back(i);
      best_y = at(i).y;
    }
  }
  return front;
}

namespace {

cv::Mat DrawScatterChart(const ScatterChart& spec) {
  cv::Mat image(spec.height, spec.width, CV_8UC3, cv::Scalar(255, 255, 255));
  const int left = 100, right = 210, top = 45, bottom = 60;
  Axis x, y;
  x.log = spec.log_x;
  y.log = spec.log_y;
  x.from = left;
  x.to = spec.width - right;
  y.from = spec.height - bottom;
  y.to = top;
  std::vector<double> xs, ys;
  int dropped = 0;
  for (const ScatterSeries& s : spec.series) {
    for (const ChartPoint& p : s.points) {
      if (x.Valid(p.x) && y.Valid(p.y)) {
        xs.push_back(p.x);
        ys.push_back(p.y);
      } else {
        ++dropped;
      }
    }
  }
  FitAxis(xs, &x);
  FitAxis(ys, &y);
  if (spec.y_min < spec.y_max) {
    y.low = y.Unit(spec.y_min);
    y.high = y.Unit(spec.y_max);
  }
  if (spec.x_min < spec.x_max) {
    x.low = x.Unit(spec.x_min);
    x.high = x.Unit(spec.x_max);
  }

  // Grid, ticks and labels.
  for (double t : x.Ticks()) {
    const int px = x.Pixel(t);
    cv::line(image, {px, y.to}, {px, y.from}, kLight);
    CentredText(&image, Format(t), px, y.from + 18, 0.4);
  }
  for (double t : y.Ticks()) {
    const int py = y.Pixel(t);
    cv::line(image, {x.from, py}, {x.to, py}, kLight);
    RightText(&image, Format(t), x.from - 6, py, 0.4);
  }
  for (double r : spec.y_reference) {
    if (!y.Valid(r) || y.Unit(r) < y.low || y.Unit(r) > y.high) continue;
    cv::line(image, {x.from, y.Pixel(r)}, {x.to, y.Pixel(r)}, kFrontColour, 1,
             cv::LINE_AA);
  }
  cv::rectangle(image, {x.from, y.to}, {x.to, y.from}, kBlack);
  std::string title = spec.title;
  if (dropped > 0) title += " (" + std::to_string(dropped) + " not shown)";
  FittedText(&image, title, {left, 28}, 0.6, spec.width - left - 10);
  CentredText(&image, spec.x_label + (spec.log_x ? " (log scale)" : ""),
              (x.from + x.to) / 2, spec.height - 15, 0.5);
  // The y label reads upwards beside the axis, clear of the title.
  VerticalText(&image, spec.y_label + (spec.log_y ? " (log scale)" : ""), 4,
               (y.from + y.to) / 2, 0.5);

  // The Pareto front: a step line through its points.
  if (spec.pareto) {
    const std::vector<std::pair<int, int>> front = ParetoFront(spec);
    cv::Point previous(-1, -1);
    for (const auto& [s, p] : front) {
      const ChartPoint& q = spec.series[s].points[p];
      if (!x.Valid(q.x) || !y.Valid(q.y)) continue;
      const cv::Point here(x.Pixel(q.x), y.Pixel(q.y));
      if (previous.x >= 0) {
        cv::line(image, previous, {here.x, previous.y}, kFrontColour, 1,
                 cv::LINE_AA);
        cv::line(image, {here.x, previous.y}, here, kFrontColour, 1,
                 cv::LINE_AA);
      }
      cv::circle(image, here, 8, kFrontColour, 1, cv::LINE_AA);
      previous = here;
    }
  }

  // Series, clipped to the plot.
  cv::Mat plot =
      image(cv::Rect(x.from, y.to, x.to - x.from + 1, y.from - y.to + 1));
  const cv::Point origin(x.from, y.to);
  bool any_highlight = false;
  for (size_t s = 0; s < spec.series.size(); ++s) {
    const ScatterSeries& series = spec.series[s];
    const cv::Scalar colour = SeriesColour(series, s);
    cv::Point previous(-1, -1);
    int segment = 0;
    for (const ChartPoint& p : series.points) {
      if (!x.Valid(p.x) || !y.Valid(p.y)) continue;
      const cv::Point here(x.Pixel(p.x), y.Pixel(p.y));
      if (series.lines && previous.x >= 0 &&
          !(series.dashed && segment++ % 2 == 1)) {
        cv::line(plot, previous - origin, here - origin, colour, 2,
                 cv::LINE_AA);
      }
      previous = here;
      if (series.markers) {
        cv::circle(plot, here - origin, series.marker_radius, colour,
                   cv::FILLED, cv::LINE_AA);
      }
      if (p.highlight) {
        cv::circle(image, here, 11, kRed, 2, cv::LINE_AA);
        any_highlight = true;
      }
      if (!p.label.empty()) {
        Text(&image, p.label, {here.x + 6, here.y - 6}, 0.35, colour);
      }
    }
    // Legend.
    const int ly = top + 18 + 20 * static_cast<int>(s);
    if (series.lines) {
      cv::line(image, {x.to + 8, ly - 4}, {x.to + 26, ly - 4}, colour, 2,
               cv::LINE_AA);
    }
    if (series.markers || !series.lines) {
      cv::circle(image, {x.to + 18, ly - 4}, 5, colour, cv::FILLED,
                 cv::LINE_AA);
    }
    Text(&image, series.name, {x.to + 30, ly}, 0.45);
  }
  int ly = top + 18 + 20 * static_cast<int>(spec.series.size()) + 10;
  if (any_highlight) {
    cv::circle(image, {x.to + 18, ly - 4}, 9, kRed, 2, cv::LINE_AA);
    Text(&image, "default", {x.to + 30, ly}, 0.45);
  }
  if (!spec.y_reference_label.empty()) {
    ly += 22;
    cv::line(image, {x.to + 8, ly - 4}, {x.to + 26, ly - 4}, kFrontColour, 1,
             cv::LINE_AA);
    Text(&image, spec.y_reference_label, {x.to + 30, ly}, 0.45);
  }
  if (spec.pareto) {
    ly += 22;
    cv::circle(image, {x.to + 18, ly - 4}, 8, kFrontColour, 1, cv::LINE_AA);
    Text(&image, "Pareto front", {x.to + 30, ly}, 0.45);
  }
  return image;
}

}  // namespace

void WriteScatterChartPng(const ScatterChart& spec, const std::string& path) {
  WritePng(DrawScatterChart(spec), path);
}

void WriteScatterChartsPng(const std::vector<ScatterChart>& charts,
                           const std::string& path) {
  std::vector<cv::Mat> images;
  int width = 0;
  for (const ScatterChart& c : charts) {
    images.push_back(DrawScatterChart(c));
    width = std::max(width, images.back().cols);
  }
  for (cv::Mat& m : images) {
    if (m.cols < width) {
      cv::copyMakeBorder(m, m, 0, 0, 0, width - m.cols, cv::BORDER_CONSTANT,
                         cv::Scalar(255, 255, 255));
    }
  }
  cv::Mat all;
  cv::vconcat(images, all);
  WritePng(all, path);
}

}  // namespace clothfit
