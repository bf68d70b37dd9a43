// Polar plots of BRDF slices in the plane of incidence (chart.h
// WritePolarPlotPng), in the style of Daubert et al. 2001, Figs. 3-8.
#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "charts/draw_internal.h"
#include "models/math.h"

namespace clothfit {
namespace {

using namespace chart_internal;  // NOLINT: the drawers' shared helpers

constexpr int kRadius = 160;               // pixels, the rim
constexpr int kPanelW = 2 * kRadius + 90;  // room for the angle labels
constexpr int kPanelH = kRadius + 95;      // title above, ring labels below
constexpr int kColumns = 4;
constexpr int kHeader = 62;  // figure title and legend

// The radial scale: the larger of the largest measured value and the 90th
// percentile of the model's curve points, so that neither a model's narrow
// peak (a specular lobe hundreds of times the rest) flattens everything
// else nor a couple of dim rows flatten the model; beyond it the curve is
// clipped at the rim.
double RadialScale(const std::vector<PolarPanel>& panels) {
  double measured = 0.0;
  std::vector<double> model;
  for (const PolarPanel& p : panels) {
    for (double v : p.measured_value) {
      if (std::isfinite(v)) measured = std::max(measured, v);
    }
    for (double v : p.model_value) {
      if (std::isfinite(v)) model.push_back(v);
    }
  }
  double typical = 0.0;
  if (!model.empty()) {
    const auto at = model.begin() + (model.size() * 9) / 10;
    std::nth_element(model.begin(), at, model.end());
    typical = *at;
  }
  const double scale = std::max(measured, typical);
  return scale > 0.0 ? scale : 1.0;
}

void DrawPanel(const PolarPanel& p, double scale, cv::Mat* panel) {
  const cv::Point centre(kPanelW / 2, kPanelH - 40);
  auto at = [&](double angle_deg, double value) {
    const double a = Radians(angle_deg);
    const double r = kRadius * std::max(0.0, value) / scale;
    return cv::Point(centre.x + static_cast<int>(std::lround(r * std::sin(a))),
                     centre.y - static_cast<int>(std::lround(r * std::cos(a))));
  };
  // Rings at round values, labelled along the baseline right of the
  // centre; spokes every 30 degrees, labelled outside the rim.
  Axis radial;
  radial.low = 0.0;
  radial.high = scale;
  for (double v : radial.Ticks()) {
    if (!(v > 0.0)) continue;
    const int r = static_cast<int>(std::lround(kRadius * v / scale));
    cv::ellipse(*panel, centre, {r, r}, 0, 180, 360, kLight, 1, cv::LINE_AA);
    cv::line(*panel, {centre.x + r, centre.y}, {centre.x + r, centre.y + 4},
             kGrey);
    CentredText(panel, Format(v), centre.x + r, centre.y + 18, 0.35);
  }
  cv::ellipse(*panel, centre, {kRadius, kRadius}, 0, 180, 360, kGrey, 1,
              cv::LINE_AA);
  for (int a = -90; a <= 90; a += 30) {
    cv::line(*panel, centre, at(a, scale), kLight, 1, cv::LINE_AA);
    const cv::Point label = at(a, scale * (kRadius + 18.0) / kRadius);
    CentredText(panel, std::to_string(a), label.x, label.y + 5, 0.35);
  }
  cv::line(*panel, {centre.x - kRadius, centre.y},
           {centre.x + kRadius, centre.y}, kGrey);
  // The light: an arrow from the rim towards the centre at -theta_i.
  cv::arrowedLine(*panel, at(-p.incidence_deg, scale), centre, kRed, 1,
                  cv::LINE_AA, 0, 0.04);
  // The curve, drawn on a copy and kept inside the rim: nothing runs into
  // the labels or a neighbour.
  cv::Mat curve = panel->clone();
  for (size_t k = 1; k < p.model_angle_deg.size(); ++k) {
    if (!std::isfinite(p.model_value[k - 1]) ||
        !std::isfinite(p.model_value[k])) {
      continue;
    }
    cv::line(curve, at(p.model_angle_deg[k - 1], p.model_value[k - 1]),
             at(p.model_angle_deg[k], p.model_value[k]), PaletteColour(0), 2,
             cv::LINE_AA);
  }
  cv::Mat inside(panel->size(), CV_8UC1, cv::Scalar(0));
  cv::circle(inside, centre, kRadius + 1, cv::Scalar(255), cv::FILLED);
  curve.copyTo(*panel, inside);
  for (size_t k = 0; k < p.measured_angle_deg.size(); ++k) {
    if (!std::isfinite(p.measured_value[k])) continue;
    cv::circle(*panel, at(p.measured_angle_deg[k], p.measured_value[k]), 3,
               PaletteColour(1), cv::FILLED, cv::LINE_AA);
  }
  CentredText(panel, p.title, kPanelW / 2, 18, 0.45);
  CentredText(panel, "theta_o (deg)", centre.x, centre.y + 34, 0.38,
              kFrontColour);
}

}  // namespace

void WritePolarPlotPng(const std::vector<PolarPanel>& panels,
                       const std::string& title, const std::string& path,
                       const std::string& value_label) {
  const int n = std::max<int>(1, static_cast<int>(panels.size()));
  const int columns = std::min(n, kColumns);
  const int rows = (n + kColumns - 1) / kColumns;
  const int width = std::max(kPanelW * columns, 560);
  cv::Mat image(kHeader + kPanelH * rows, width, CV_8UC3,
                cv::Scalar(255, 255, 255));
  const double scale = RadialScale(panels);
  bool clipped = false;
  for (const PolarPanel& p : panels) {
    for (double v : p.model_value) clipped = clipped || v > scale;
  }
  FittedText(&image, title, {10, 24}, 0.55, width - 20);
  // Legend.
  cv::circle(image, {16, 46}, 4, PaletteColour(1), cv::FILLED, cv::LINE_AA);
  Text(&image, "measured", {26, 51}, 0.42);
  cv::line(image, {110, 46}, {134, 46}, PaletteColour(0), 2, cv::LINE_AA);
  Text(&image, "model", {140, 51}, 0.42);
  cv::arrowedLine(image, {205, 46}, {229, 46}, kRed, 1, cv::LINE_AA, 0, 0.3);
  Text(&image,
       "light;  radius: " + value_label +
           (clipped ? ";  model clipped at the outer ring" : ""),
       {235, 51}, 0.42);
  for (size_t i = 0; i < panels.size(); ++i) {
    const int column = static_cast<int>(i) % kColumns;
    const int row = static_cast<int>(i) / kColumns;
    cv::Mat panel = image(
        cv::Rect(column * kPanelW, kHeader + row * kPanelH, kPanelW, kPanelH));
    DrawPanel(panels[i], scale, &panel);
  }
  WritePng(image, path);
}

}  // namespace clothfit
