#include "report/fit_figures.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "export/png.h"
#include "fitting/energy.h"
#include "models/math.h"
#include "render/sphere.h"

namespace clothfit {
namespace {

double Grey(const glm::dvec3& v) { return (v.x + v.y + v.z) / 3.0; }

ChartPoint Point(double x, double y) {
  ChartPoint p;
  p.x = x;
  p.y = y;
  return p;
}

// The angle between two directions (models/math.h: accurate near 0 and pi).
double DirectionAngle(const glm::dvec3& a, const glm::dvec3& b) {
  return AngleBetween(a, b, glm::length(a) * glm::length(b));
}

double PolarAngle(const glm::dvec3& w) {
  double theta = 0.0, phi = 0.0;
  AnglesFromDirection(w, &theta, &phi);
  return theta;
}

// " [1/sr]" for the BRDF and rho (both per steradian).
std::string ValueUnit(Quantity q) {
  return q == Quantity::kTransmittance ? "" : " (1/sr)";
}

std::string ValueLabel(Quantity q) {
  return std::string(QuantityName(q)) + ValueUnit(q);
}

// Log axes when the positive values span more than a factor of 30.
bool WantsLog(const std::vector<double>& values) {
  double lo = HUGE_VAL, hi = 0.0;
  for (double v : values) {
    if (v > 0.0 && std::isfinite(v)) {
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  }
  return hi > 30.0 * lo;
}

ScatterChart ScatterFigure(const RowComparison& rows, Quantity q,
                           const std::string& label) {
  ScatterChart chart;
  chart.title = label + ": model against measured, all " +
                std::to_string(rows.measured.size()) + " rows";
  chart.x_label = "measured " + ValueLabel(q);
  chart.y_label = "model " + ValueLabel(q);
  std::vector<double> all = rows.measured;
  all.insert(all.end(), rows.model.begin(), rows.model.end());
  chart.log_x = chart.log_y = WantsLog(all);
  ScatterSeries points;
  points.name = "table rows";
  points.marker_radius = rows.measured.size() > 1000 ? 2 : 3;
  double lo = HUGE_VAL, hi = -HUGE_VAL;
  for (size_t i = 0; i < rows.measured.size(); ++i) {
    points.points.push_back(Point(rows.measured[i], rows.model[i]));
    for (double v : {rows.measured[i], rows.model[i]}) {
      if (std::isfinite(v) && (!chart.log_x || v > 0.0)) {
        lo = std::min(lo, v);
        hi = std::max(hi, v);
      }
    }
  }
  chart.series.push_back(points);
  if (lo < hi) {  // the same range on both axes, and the diagonal
    ScatterSeries diagonal;
    diagonal.name = "model = measured";
    diagonal.lines = true;
    diagonal.markers = false;
    diagonal.colour = Rgb8{90, 90, 90};
    diagonal.points = {Point(lo, lo), Point(hi, hi)};
    chart.series.push_back(diagonal);
  }
  chart.width = 820;
  chart.height = 640;
  return chart;
}

std::vector<ScatterChart> ResidualFigures(const RowComparison& rows,
                                          const std::string& label) {
  std::vector<double> relative(rows.measured.size());
  for (size_t i = 0; i < relative.size(); ++i) {
    relative[i] =
        rows.measured[i] > 0.0
            ? 100.0 * (rows.model[i] - rows.measured[i]) / rows.measured[i]
            : std::nan("");  // counted as "not shown"
  }
  struct Against {
    const std::vector<double>* x;
    std::string name, axis;
  };
  const Against against[] = {
      {&rows.theta_i_deg, "theta_i", "theta_i, light's polar angle (deg)"},
      {&rows.theta_o_deg, "theta_o", "theta_o, view's polar angle (deg)"},
      {&rows.phase_deg, "the phase angle",
       "phase angle between wi and wo (deg)"}};
  std::vector<ScatterChart> charts;
  for (const auto& [x, name, axis] : against) {
    ScatterChart chart;
    chart.title = label + ": relative residual of every row against " + name;
    if (charts.empty())
      chart.title += " (" + std::to_string(relative.size()) + " rows)";
    chart.x_label = axis;
    chart.y_label = "residual (model/measured - 1, %)";
    chart.x_min = 0.0;
    chart.x_max = x == &rows.phase_deg ? 180.0 : 90.0;
    chart.y_reference = {0.0};
    chart.y_reference_label = "model = measured";
    ScatterSeries s;
    s.name = "table rows";
    s.marker_radius = relative.size() > 1000 ? 2 : 3;
    for (size_t i = 0; i < relative.size(); ++i) {
      s.points.push_back(Point((*x)[i], relative[i]));
    }
    chart.series.push_back(s);
    chart.width = 900;
    chart.height = 300;
    charts.push_back(chart);
  }
  return charts;
}

}  // namespace

bool FigureNeedsData(const std::string& name) {
  return name == "scatter" || name == "residuals" || name == "polar";
}

double PhaseAngle(const glm::dvec3& wi, const glm::dvec3& wo) {
  return DirectionAngle(wi, wo);
}

HalfDiff ToHalfDiff(const glm::dvec3& wi, const glm::dvec3& wo) {
  HalfDiff a;
  const glm::dvec3 h = glm::normalize(wi + wo);
  a.theta_h = PolarAngle(h);
  a.phi_h = std::atan2(h.y, h.x);
  // wi rotated by -phi_h about z, then by -theta_h about y.
  const double cp = std::cos(a.phi_h), sp = std::sin(a.phi_h);
  const glm::dvec3 r1(cp * wi.x + sp * wi.y, -sp * wi.x + cp * wi.y, wi.z);
  const double ct = std::cos(a.theta_h), st = std::sin(a.theta_h);
  const glm::dvec3 d(ct * r1.x - st * r1.z, r1.y, st * r1.x + ct * r1.z);
  a.theta_d = PolarAngle(d);
  a.phi_d = std::atan2(d.y, d.x);
  return a;
}

std::pair<glm::dvec3, glm::dvec3> FromHalfDiff(const HalfDiff& a) {
  const glm::dvec3 d(std::sin(a.theta_d) * std::cos(a.phi_d),
                     std::sin(a.theta_d) * std::sin(a.phi_d),
                     std::cos(a.theta_d));
  // Rotate by theta_h about y, then by phi_h about z.
  const double ct = std::cos(a.theta_h), st = std::sin(a.theta_h);
  const glm::dvec3 r1(ct * d.x + st * d.z, d.y, -st * d.x + ct * d.z);
  const double cp = std::cos(a.phi_h), sp = std::sin(a.phi_h);
  const glm::dvec3 wi(cp * r1.x - sp * r1.y, sp * r1.x + cp * r1.y, r1.z);
  const glm::dvec3 h(st * cp, st * sp, ct);
  return {wi, 2.0 * glm::dot(wi, h) * h - wi};
}

RowComparison CompareRows(const ModelParams& model,
                          const MeasurementTable& table) {
  RowComparison out;
  for (const TableRow& row : table.rows) {
    out.measured.push_back(Grey(row.value));
    out.model.push_back(Grey(Evaluate(model, row.wi, row.wo, table.quantity)));
    out.theta_i_deg.push_back(Degrees(PolarAngle(row.wi)));
    out.theta_o_deg.push_back(Degrees(PolarAngle(row.wo)));
    out.phase_deg.push_back(Degrees(PhaseAngle(row.wi, row.wo)));
  }
  return out;
}

std::vector<PolarPanel> PolarPanels(const ModelParams& model,
                                    const MeasurementTable& table,
                                    const PlotOptions& options, size_t* shown) {
  const double phi = Radians(options.phi_deg);
  const double window = Radians(options.window_deg);
  // In-plane unit vector towards the light's azimuth, and the normal of the
  // plane of incidence.
  const glm::dvec3 u(std::cos(phi), std::sin(phi), 0.0);
  const glm::dvec3 across(-std::sin(phi), std::cos(phi), 0.0);
  std::vector<char> in_any(table.rows.size(), 0);
  std::vector<PolarPanel> panels;
  for (double deg : options.incidence_deg) {
    PolarPanel panel;
    panel.incidence_deg = deg;
    const double ti = Radians(deg);
    const glm::dvec3 wi = std::sin(ti) * u + glm::dvec3(0, 0, std::cos(ti));
    for (int a = -89; a <= 89; ++a) {
      const double to = Radians(static_cast<double>(a));
      const glm::dvec3 wo = -std::sin(to) * u + glm::dvec3(0, 0, std::cos(to));
      panel.model_angle_deg.push_back(a);
      panel.model_value.push_back(
          Grey(Evaluate(model, wi, wo, table.quantity)));
    }
    for (size_t r = 0; r < table.rows.size(); ++r) {
      const TableRow& row = table.rows[r];
      if (!(row.wo.z > 0.0) || DirectionAngle(row.wi, wi) > window) continue;
      const double off_plane =
          std::asin(std::clamp(glm::dot(row.wo, across), -1.0, 1.0));
      if (std::abs(off_plane) > window) continue;
      in_any[r] = 1;
      panel.measured_angle_deg.push_back(
          Degrees(std::atan2(-glm::dot(row.wo, u), row.wo.z)));
      panel.measured_value.push_back(Grey(row.value));
    }
    char title[120];
    std::snprintf(title, sizeof(title), "theta_i = %g deg: %zu of %zu rows",
                  deg, panel.measured_value.size(), table.rows.size());
    panel.title = title;
    panels.push_back(std::move(panel));
  }
  if (shown)
    *shown = static_cast<size_t>(std::count(in_any.begin(), in_any.end(), 1));
  return panels;
}

ImageChart HalfDiffChart(const ModelParams& model, Quantity quantity,
                         int cells) {
  ImageChart chart;
  chart.title = "the model over Rusinkiewicz's half/difference angles";
  chart.x_label = "theta_h, half vector's polar angle (deg)";
  chart.y_label = "theta_d, difference angle (deg)";
  chart.colour_label = ValueLabel(quantity);
  chart.note =
      "phi_d = 90 deg, phi_h = 0 deg (half vector in the warp-normal "
      "plane); grey: wi or wo below the surface";
  chart.columns = chart.rows = cells;
  chart.x_high = chart.y_high = 90.0;
  chart.cell_pixels = std::max(1, 450 / cells);
  for (int r = 0; r < cells; ++r) {
    const double theta_d = Radians(90.0 * (cells - r - 0.5) / cells);
    for (int c = 0; c < cells; ++c) {
      HalfDiff a;
      a.theta_h = Radians(90.0 * (c + 0.5) / cells);
      a.theta_d = theta_d;
      a.phi_d = Radians(90.0);
      const auto [wi, wo] = FromHalfDiff(a);
      chart.values.push_back(wi.z > 0.0 && wo.z > 0.0
                                 ? Grey(Evaluate(model, wi, wo, quantity))
                                 : std::nan(""));
    }
  }
  chart.log_colour = WantsLog(chart.values);
  return chart;
}

ScatterChart AlbedoChart(const ModelParams& model) {
  ScatterChart chart;
  chart.title =
      "directional albedo: light reflected towards wo under a "
      "uniform white sky";
  chart.x_label = "theta_o, view's polar angle (deg)";
  chart.y_label = "albedo a(wo), mean of r,g,b (unitless)";
  chart.x_min = 0.0;
  chart.x_max = 90.0;
  chart.y_reference = {1.0};
  chart.y_reference_label = "energy bound";
  const HemisphereQuadrature q = MakeHemisphereQuadrature(36);
  for (double phi_deg : {0.0, 45.0, 90.0}) {
    ScatterSeries s;
    s.name = "phi_o = " + std::to_string(static_cast<int>(phi_deg)) + " deg";
    s.lines = true;
    s.marker_radius = 2;
    const double phi = Radians(phi_deg);
    for (int t = 0; t <= 87; t += 3) {
      const double theta = Radians(static_cast<double>(t));
      const glm::dvec3 wo(std::sin(theta) * std::cos(phi),
                          std::sin(theta) * std::sin(phi), std::cos(theta));
      s.points.push_back(Point(t, Grey(ModelViewAlbedo(model, wo, q))));
    }
    chart.series.push_back(s);
  }
  double top = 1.05;
  for (const ScatterSeries& s : chart.series) {
    for (const ChartPoint& p : s.points) {
      if (std::isfinite(p.y)) top = std::max(top, 1.05 * p.y);
    }
  }
  chart.y_min = 0.0;
  chart.y_max = top;  // 0 and the energy bound 1 always in view
  return chart;
}

Picture SphereFigure(const ModelParams& model, const std::string& label,
                     int size, double* exposure_out) {
  const PreviewImage image = RenderSphere(model, kSphereLight, 1.0, size);
  const double exposure = AutoExposure(image);
  if (exposure_out) *exposure_out = exposure;
  Picture picture;
  picture.title = label + ": lit sphere";
  picture.width = picture.height = size;
  // Off the sphere (render/sphere.h's pixel centres): grey, so that the
  // unlit side (black) shows the silhouette.
  for (int j = 0; j < size; ++j) {
    for (int i = 0; i < size; ++i) {
      const double x = (i + 0.5) * 2.0 / size - 1.0;
      const double y = 1.0 - (j + 0.5) * 2.0 / size;
      const glm::dvec3& p = image.At(i, j);
      picture.pixels.push_back(x * x + y * y >= 1.0
                                   ? kSphereBackground
                                   : Rgb8{SrgbByte(p.x * exposure),
                                          SrgbByte(p.y * exposure),
                                          SrgbByte(p.z * exposure)});
    }
  }
  char line[160];
  std::snprintf(line, sizeof(line),
                "radiance f(wi, wo) max(wi.z, 0) E, E = 1; exposure %.3g "
                "(99th percentile -> white), sRGB",
                exposure);
  picture.caption = {
      "orthographic view down -z; at each point the surface frame of its "
      "normal (warp horizontal at the centre)",
      "one directional light at theta 45 deg, phi 135 deg (upper left)", line};
  return picture;
}

WrittenFigures WriteFitFigures(
    const ModelParams& model, const std::string& label,
    const MeasurementTable* table, const std::vector<std::string>& names,
    const PlotOptions& options,
    const std::function<std::string(const std::string&)>& path_of) {
  WrittenFigures out;
  const Quantity quantity = table ? table->quantity : Quantity::kBrdf;
  RowComparison rows;
  if (table) rows = CompareRows(model, *table);
  for (const std::string& name : names) {
    if (FigureNeedsData(name) && !table) {
      out.notes.push_back("note: " + name + " needs a table (--data): skipped");
      continue;
    }
    const std::string path = path_of(name);
    if (name == "scatter") {
      WriteScatterChartPng(ScatterFigure(rows, quantity, label), path);
    } else if (name == "residuals") {
      WriteScatterChartsPng(ResidualFigures(rows, label), path);
    } else if (name == "polar") {
      const WrittenFigures polar =
          WritePolarFigure(model, label, *table, options, path);
      out.notes.insert(out.notes.end(), polar.notes.begin(), polar.notes.end());
    } else if (name == "halfdiff") {
      ImageChart chart = HalfDiffChart(model, quantity);
      chart.title = label + ": " + chart.title;
      WriteImageChartPng(chart, path);
    } else if (name == "sphere") {
      WritePicturePng(SphereFigure(model, label, options.sphere_pixels), path);
    } else if (name == "albedo") {
      ScatterChart chart = AlbedoChart(model);
      chart.title = label + ": " + chart.title;
      WriteScatterChartPng(chart, path);
    } else {
      continue;  // the caller checks the names
    }
    out.files.emplace_back(name, path);
  }
  return out;
}

WrittenFigures WritePolarFigure(const ModelParams& model,
                                const std::string& label,
                                const MeasurementTable& table,
                                const PlotOptions& options,
                                const std::string& path) {
  WrittenFigures out;
  size_t shown = 0;
  const std::vector<PolarPanel> panels =
      PolarPanels(model, table, options, &shown);
  char title[200];
  std::snprintf(title, sizeof(title),
                "%s: slices in the plane of incidence at phi = %g deg "
                "(rows within %g deg)",
                label.c_str(), options.phi_deg, options.window_deg);
  WritePolarPlotPng(panels, title, path, ValueLabel(table.quantity));
  out.files.emplace_back("polar", path);
  if (2 * shown < table.rows.size()) {
    out.notes.push_back(
        "warning: the polar panels show " + std::to_string(shown) + " of " +
        std::to_string(table.rows.size()) +
        " rows (the rest lie off their planes); the scatter and residuals "
        "figures show every row");
  }
  return out;
}

}  // namespace clothfit
