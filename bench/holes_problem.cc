#include "bench/holes_problem.h"

#include <cmath>
#include <limits>

#include "data_synthetic/holes_truth.h"

namespace clothfit {

namespace {

// One row per (theta, phi) in degrees with value(wo).
template <typename F>
MeasurementTable TableOfViews(const std::vector<double>& thetas_deg,
                              const std::vector<double>& phis_deg, F value) {
  MeasurementTable table;
  table.quantity = Quantity::kTransmittance;
  table.channels = 1;
  for (double theta : thetas_deg) {
    for (double phi : phis_deg) {
      TableRow row;
      row.wo = DirectionFromAngles(Radians(theta), Radians(phi));
      row.value = glm::dvec3(value(row.wo));
      table.rows.push_back(row);
    }
  }
  return table;
}

}  // namespace

MeasurementTable HolesTruthTable(const Mask& mask, const HolesParams& truth,
                                 const std::vector<double>& thetas_deg,
                                 const std::vector<double>& phis_deg,
                                 int samples) {
  return TableOfViews(thetas_deg, phis_deg, [&](const glm::dvec3& wo) {
    const HoleRatios ratios =
        HoleTruthTile(mask, ViewOffset(truth.thickness_texels, wo), samples);
    return TransmittanceOfRatios(truth, ratios).x;
  });
}

MeasurementTable HolesModelTable(const HolesTile& tile,
                                 const HolesParams& truth,
                                 const std::vector<double>& thetas_deg,
                                 const std::vector<double>& phis_deg) {
  return TableOfViews(thetas_deg, phis_deg, [&](const glm::dvec3& wo) {
    return HolesTransmittance(truth, tile, wo).x;
  });
}

double HolesHeldOutError(const HolesParams& fitted, const HolesTile& tile,
                         const MeasurementTable& truth) {
  double se = 0.0, ss = 0.0;
  for (const TableRow& row : truth.rows) {
    const double m = HolesTransmittance(fitted, tile, row.wo).x;
    se += (m - row.value.x) * (m - row.value.x);
    ss += row.value.x * row.value.x;
  }
  return ss > 0.0 ? std::sqrt(se / ss)
                  : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace clothfit
