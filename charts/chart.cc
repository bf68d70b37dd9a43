#include "charts/chart.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "io/atomic_file.h"
#include "io/input_error.h"
#include "io/text_util.h"
#include "models/math.h"

namespace clothfit {
namespace {

const cv::Scalar kBlack(0, 0, 0), kGrey(170, 170, 170), kLight(235, 235, 235),
    kRed(30, 30, 220), kFrontColour(60, 60, 60);
// Series colours (BGR): blue, orange, green, purple, brown, pink, olive.
const cv::Scalar kPalette[] = {{180, 119, 31},  {14, 127, 255}, {44, 160, 44},
                               {189, 103, 148}, {75, 86, 140},  {194, 119, 227},
                               {34, 189, 188}};
constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;

cv::Scalar PaletteColour(size_t i) {
  return kPalette[i % (sizeof(kPalette) / sizeof(kPalette[0]))];
}

// A series' own colour, else the palette's for index i.
cv::Scalar SeriesColour(const ScatterSeries& series, size_t i) {
  if (!series.colour) return PaletteColour(i);
  const Rgb8& c = *series.colour;
  return cv::Scalar(c[2], c[1], c[0]);
}

void Text(cv::Mat* image, const std::string& text, cv::Point at,
          double scale = 0.45, const cv::Scalar& colour = kBlack) {
  cv::putText(*image, text, at, kFont, scale, colour, 1, cv::LINE_AA);
}

std::string Format(double v) { return text_util::FormatNumber(v, 6); }

// One axis: data range to pixels, linear or log10.
struct Axis {
  bool log = false;
  double low = 0.0, high = 1.0;  // in axis units (log10 for log axes)
  int from = 0, to = 1;          // pixels

  double Unit(double v) const { return log ? std::log10(v) : v; }
  bool Valid(double v) const { return std::isfinite(v) && (!log || v > 0.0); }
  int Pixel(double v) const {
    const double u = (Unit(v) - low) / (high - low);
    return static_cast<int>(std::lround(from + u * (to - from)));
  }
  // Tick values (data units).
  std::vector<double> Ticks() const {
    std::vector<double> ticks;
    if (log) {
      const int a = static_cast<int>(std::floor(low)),
                b = static_cast<int>(std::ceil(high));
      const bool dense = b - a <= 2;
      for (int e = a; e <= b; ++e) {
        for (double m :
             dense ? std::vector<double>{1, 2, 5} : std::vector<double>{1}) {
          const double v = m * std::pow(10.0, e);
          if (Unit(v) >= low - 1e-9 && Unit(v) <= high + 1e-9) {
            ticks.push_back(v);
          }
        }
      }
      if (ticks.size() >= 3) return ticks;
      ticks.clear();  // less than a decade: linear ticks in data units
      Axis linear;
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
};

// Range of the valid values, padded; a single value gets a unit range.
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

void WritePng(const cv::Mat& image, const std::string& path) {
  std::vector<unsigned char> bytes;
  if (!cv::imencode(".png", image, bytes)) {
    throw InputError(path + ": cannot encode the PNG");
  }
  WriteFileAtomically(path, std::string(bytes.begin(), bytes.end()));
}

}  // namespace

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

void WriteScatterChartPng(const ScatterChart& spec, const std::string& path) {
  cv::Mat image(spec.height, spec.width, CV_8UC3, cv::Scalar(255, 255, 255));
  const int left = 80, right = 210, top = 45, bottom = 60;
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

  // Grid, ticks and labels.
  for (double t : x.Ticks()) {
    const int px = x.Pixel(t);
    cv::line(image, {px, y.to}, {px, y.from}, kLight);
    Text(&image, Format(t), {px - 12, y.from + 18}, 0.4);
  }
  for (double t : y.Ticks()) {
    const int py = y.Pixel(t);
    cv::line(image, {x.from, py}, {x.to, py}, kLight);
    Text(&image, Format(t), {8, py + 4}, 0.4);
  }
  cv::rectangle(image, {x.from, y.to}, {x.to, y.from}, kBlack);
  std::string title = spec.title;
  if (dropped > 0) title += " (" + std::to_string(dropped) + " not shown)";
  Text(&image, title, {left, 28}, 0.6);
  Text(&image, spec.x_label + (spec.log_x ? " (log)" : ""),
       {(x.from + x.to) / 2 - 60, spec.height - 15}, 0.5);
  Text(&image, spec.y_label + (spec.log_y ? " (log)" : ""), {8, top - 8}, 0.45);

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
        cv::circle(plot, here - origin, 4, colour, cv::FILLED, cv::LINE_AA);
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
  if (spec.pareto) {
    ly += 22;
    cv::circle(image, {x.to + 18, ly - 4}, 8, kFrontColour, 1, cv::LINE_AA);
    Text(&image, "Pareto front", {x.to + 30, ly}, 0.45);
  }
  WritePng(image, path);
}

void WritePolarPlotPng(const std::vector<PolarPanel>& panels,
                       const std::string& title, const std::string& path) {
  const int panel_w = 360, panel_h = 230, top = 40;
  const int n = std::max<int>(1, static_cast<int>(panels.size()));
  cv::Mat image(top + panel_h + 40, panel_w * n, CV_8UC3,
                cv::Scalar(255, 255, 255));
  double max_value = 0.0;
  for (const PolarPanel& p : panels) {
    for (double v : p.measured_value) {
      if (std::isfinite(v)) max_value = std::max(max_value, v);
    }
    for (double v : p.model_value) {
      if (std::isfinite(v)) max_value = std::max(max_value, v);
    }
  }
  if (!(max_value > 0.0)) max_value = 1.0;
  Text(&image, title, {10, 25}, 0.6);
  const double radius = panel_h - 30;
  for (size_t i = 0; i < panels.size(); ++i) {
    const PolarPanel& p = panels[i];
    const cv::Point centre(static_cast<int>(panel_w * i + panel_w / 2),
                           top + panel_h);
    auto at = [&](double angle_deg, double value) {
      const double a = Radians(angle_deg);
      const double r = radius * std::max(0.0, value) / max_value;
      return cv::Point(
          centre.x + static_cast<int>(std::lround(r * std::sin(a))),
          centre.y - static_cast<int>(std::lround(r * std::cos(a))));
    };
    for (double f : {0.25, 0.5, 0.75, 1.0}) {
      cv::ellipse(image, centre,
                  {static_cast<int>(radius * f), static_cast<int>(radius * f)},
                  0, 180, 360, kLight, 1, cv::LINE_AA);
    }
    cv::line(image, {centre.x - static_cast<int>(radius), centre.y},
             {centre.x + static_cast<int>(radius), centre.y}, kGrey);
    cv::line(image, centre, {centre.x, centre.y - static_cast<int>(radius)},
             kLight);
    // The light: an arrow from the rim towards the centre at -theta_i.
    const double li = -Radians(p.incidence_deg);
    const cv::Point rim(
        centre.x + static_cast<int>(std::lround(radius * std::sin(li))),
        centre.y - static_cast<int>(std::lround(radius * std::cos(li))));
    cv::arrowedLine(image, rim, centre, kGrey, 1, cv::LINE_AA, 0, 0.05);
    for (size_t k = 1; k < p.model_angle_deg.size(); ++k) {
      if (!std::isfinite(p.model_value[k - 1]) ||
          !std::isfinite(p.model_value[k])) {
        continue;
      }
      cv::line(image, at(p.model_angle_deg[k - 1], p.model_value[k - 1]),
               at(p.model_angle_deg[k], p.model_value[k]), PaletteColour(0), 2,
               cv::LINE_AA);
    }
    for (size_t k = 0; k < p.measured_angle_deg.size(); ++k) {
      if (!std::isfinite(p.measured_value[k])) continue;
      cv::circle(image, at(p.measured_angle_deg[k], p.measured_value[k]), 3,
                 PaletteColour(1), cv::FILLED, cv::LINE_AA);
    }
    Text(&image, p.title,
         {static_cast<int>(panel_w * i + 10), top + panel_h + 25}, 0.45);
  }
  Text(&image, "dots: measured, line: model, radius 0.." + Format(max_value),
       {10, top + 8}, 0.4, kFrontColour);
  WritePng(image, path);
}

}  // namespace clothfit
