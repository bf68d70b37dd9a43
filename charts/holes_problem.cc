#include "charts/holes_problem.h"

#include <cmath>
#include <limits>

#include "data_synthetic/holes_truth.h"

namespace clothfit {

namespace {

// One row per (theta, phi) in degrees with value(wo).
template <typename F>
MeasurementTable ViewTable(const std::vector<double>& thetas_deg,
                           const std::vector<double>& phis_deg, F value) {
  MeasurementTable table;
  table.quantity = Quantity::kTransmittance;
  table.channels = 1;
  for (double theta : thetas_deg) {
    for (double phi : phis_deg) {
      TableRow row;
      row.wo = DirectionFromAngles(theta * kPi / 180.0, phi * kPi / 180.0);
      row.value = glm::dvec3(value(row.wo));
      table.rows.push_back(row);
    }
  }
  return table;
}

LevelTexels Level(const HoleTexture& texture, int level) {
  return GatherLevel(texture, level < 0 ? texture.counts.levels() - 1 : level);
}

double ModelValue(const HolesParams& p, const LevelTexels& texels,
                  HoleMethod method, const glm::dvec3& wo) {
  return HolesTransmittance(
             p, TileRatios(texels, method, ViewOffset(p.thickness_texels, wo)))
      .x;
}

}  // namespace

MeasurementTable HolesTruthTable(const Mask& mask, const HolesParams& truth,
                                 const std::vector<double>& thetas_deg,
                                 const std::vector<double>& phis_deg,
                                 int samples) {
  return ViewTable(thetas_deg, phis_deg, [&](const glm::dvec3& wo) {
    const HoleRatios ratios =
        HoleTruthTile(mask, ViewOffset(truth.thickness_texels, wo), samples);
    return HolesTransmittance(truth, ratios).x;
  });
}

MeasurementTable HolesModelTable(const HoleTexture& texture,
                                 const HolesParams& truth, HoleMethod method,
                                 int level,
                                 const std::vector<double>& thetas_deg,
                                 const std::vector<double>& phis_deg) {
  const LevelTexels texels = Level(texture, level);
  return ViewTable(thetas_deg, phis_deg, [&](const glm::dvec3& wo) {
    return ModelValue(truth, texels, method, wo);
  });
}

double HolesHeldOutError(const HolesParams& fitted, const HoleTexture& texture,
                         HoleMethod method, int level,
                         const MeasurementTable& truth) {
  const LevelTexels texels = Level(texture, level);
  double se = 0.0, ss = 0.0;
  for (const TableRow& row : truth.rows) {
    const double m = ModelValue(fitted, texels, method, row.wo);
    se += (m - row.value.x) * (m - row.value.x);
    ss += row.value.x * row.value.x;
  }
  return ss > 0.0 ? std::sqrt(se / ss)
                  : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace clothfit
