// clothfit plot: polar plots of a model against measured values in the
// plane of incidence, a panel per incidence angle (like Daubert et al.
// 2001, Figs. 3-8).
#include <cmath>
#include <cstdio>
#include <sstream>

#include "apps/commands.h"
#include "charts/chart.h"
#include "io/atomic_file.h"
#include "io/text_util.h"

namespace clothfit {
namespace {

// Mean of the three channels (the plot's value).
double Grey(const glm::dvec3& v) { return (v.x + v.y + v.z) / 3.0; }

}  // namespace

int RunPlot(int argc, char** argv) {
  CommandArgs args(
      "plot",
      "clothfit plot (--params P.json | --preset NAME) --data T.csv --out "
      "plot.png [--incidence-deg LIST] [--phi-deg PHI] [--window-deg W]",
      "Draws, for each incidence angle, the slice of the model in the plane "
      "of incidence at azimuth PHI\n(a curve) and the measured rows near it "
      "(dots: theta_i and phi_i within W of the panel's, wo\nwithin W of the "
      "plane), as a polar plot: angle = theta_o (positive: away from the "
      "light), radius =\nthe value (mean of r,g,b) in the table's quantity.");
  args.Option("params", "P.json", "parameter file (SPEC §4)");
  args.Option("preset", "NAME", "a preset instead of --params");
  args.Option("data", "T.csv", "measurement table (SPEC §2)");
  args.Option("out", "plot.png", "output PNG");
  args.Option("incidence-deg", "LIST", "incidence angles, comma-separated",
              "0,30,60");
  args.Option("phi-deg", "PHI", "azimuth of the plane of incidence", "0");
  args.Option("window-deg", "W", "how far measured rows may lie from a panel",
              "5");
  if (!args.Parse(argc, argv, 2)) return 0;
  const std::string out_path = args.Required("out");
  CheckWritable(out_path);
  const MeasurementTable table = ReadTableOption(args, args.Required("data"));
  if (table.quantity == Quantity::kTransmittance) {
    args.Fail(args.Get("data") + ": plot draws reflection, not transmittance");
  }
  const ParamFile model =
      LoadEvaluableModel(args, table.quantity, args.Get("data"));
  const double phi = Radians(args.GetDouble("phi-deg"));
  const double window = Radians(args.GetDouble("window-deg"));
  if (!(window > 0.0 && window < kPi / 2)) {
    args.Fail("option '--window-deg': must be in (0, 90)");
  }
  const std::vector<double> incidences =
      NumberListOption(args, "incidence-deg");
  for (const double deg : incidences) {
    if (!(deg >= 0.0 && deg < 90.0)) {
      args.Fail("option '--incidence-deg': " + text_util::FormatNumber(deg) +
                " is not an angle in [0, 90)");
    }
  }
  // A panel each, side by side: more would not be readable, and ~3000 made
  // an image too wide for the PNG encoder.
  constexpr size_t kMaxPanels = 16;
  if (incidences.size() > kMaxPanels) {
    args.Fail("option '--incidence-deg': at most " +
              std::to_string(kMaxPanels) + " angles (a panel each), got " +
              std::to_string(incidences.size()));
  }
  // In-plane unit vector towards the light's azimuth, and the normal of the
  // plane of incidence.
  const glm::dvec3 u(std::cos(phi), std::sin(phi), 0.0);
  const glm::dvec3 across(-std::sin(phi), std::cos(phi), 0.0);
  std::vector<PolarPanel> panels;
  for (double deg : incidences) {
    PolarPanel panel;
    panel.incidence_deg = deg;
    const double ti = Radians(deg);
    const glm::dvec3 wi = std::sin(ti) * u + glm::dvec3(0, 0, std::cos(ti));
    for (int a = -89; a <= 89; ++a) {
      const double to = Radians(a);
      const glm::dvec3 wo = -std::sin(to) * u + glm::dvec3(0, 0, std::cos(to));
      panel.model_angle_deg.push_back(a);
      panel.model_value.push_back(
          Grey(Evaluate(model.params, wi, wo, table.quantity)));
    }
    for (const TableRow& row : table.rows) {
      if (!(row.wo.z > 0.0)) continue;
      // Near the panel's light: the angle between wi and the panel's.
      if (std::acos(std::clamp(glm::dot(row.wi, wi), -1.0, 1.0)) > window) {
        continue;
      }
      if (std::abs(std::asin(std::clamp(glm::dot(row.wo, across), -1.0, 1.0))) >
          window) {
        continue;
      }
      panel.measured_angle_deg.push_back(
          Degrees(std::atan2(-glm::dot(row.wo, u), row.wo.z)));
      panel.measured_value.push_back(Grey(row.value));
    }
    char title[96];
    std::snprintf(title, sizeof(title), "theta_i = %g deg (%zu rows)", deg,
                  panel.measured_value.size());
    panel.title = title;
    panels.push_back(std::move(panel));
  }
  WritePolarPlotPng(panels,
                    std::string(ModelName(model.params)) + " against " +
                        args.Get("data") + " (" +
                        std::string(QuantityName(table.quantity)) + ")",
                    out_path);
  std::printf("wrote %s\n", out_path.c_str());
  // SPEC §3.4: the tool says where the slab model is inexact.
  if (const auto* slab = std::get_if<SlabParams>(&model.params)) {
    NoteSlabRegime(*slab);
  }
  return 0;
}

}  // namespace clothfit
