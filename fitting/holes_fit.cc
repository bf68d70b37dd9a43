#include "fitting/holes_fit.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "fitting/least_squares.h"
#include "fitting/model_residual_internal.h"
#include "io/input_error.h"

namespace clothfit {
namespace {

// The tile's transmittance at row i's view.
struct HolesEvaluator {
  const MeasurementTable* table;
  const HolesTile* tile;  // shared, read only

  template <typename T>
  Vec3<T> operator()(const T* const* blocks, size_t i) const {
    HolesParamsT<T> p;
    FromArray(blocks[0], &p);
    return HolesTransmittance(p, *tile, table->rows[i].wo);
  }
};

std::vector<ParameterSpec> HolesSpecs(bool fit_wall_color) {
  std::vector<ParameterSpec> specs = ParameterSpecs(HolesParams());
  for (size_t c = 1; c < specs.size(); ++c) specs[c].free = fit_wall_color;
  return specs;
}

// Cost of h on the start grid, with each free wall-colour channel in closed
// form (the model is linear in it): c = <o, m - t> / <o, o> in [0, 1].
struct GridPoint {
  double cost = HUGE_VAL;
  HolesParams params;
};

GridPoint EvaluateStart(const MeasurementTable& table,
                        const Weighting& weighting, const HolesTile& tile,
                        const std::vector<ParameterSpec>& specs,
                        HolesParams params) {
  const size_t n = table.rows.size();
  std::vector<HoleRatios> ratios(n);
  for (size_t i = 0; i < n; ++i) {
    ratios[i] = HolesTileRatios(params, tile, table.rows[i].wo);
  }
  // The wall colour of each free channel from the weighted normal
  // equations of the model, linear in it (weights as the fit's,
  // fitting/residual_weight.h).
  for (int c = 0; c < table.channels; ++c) {
    if (!specs[1 + c].free) continue;
    double num = 0.0, den = 0.0;
    for (size_t i = 0; i < n; ++i) {
      const TableRow& row = table.rows[i];
      const double w = weighting.InverseVariance(row, 1.0)[c];
      num += w * ratios[i].occluded * (row.value[c] - ratios[i].transparent);
      den += w * Sqr(ratios[i].occluded);
    }
    if (den > 0.0) params.wall_color[c] = std::clamp(num / den, 0.0, 1.0);
  }
  GridPoint point;
  point.cost = 0.0;
  for (size_t i = 0; i < n; ++i) {
    const TableRow& row = table.rows[i];
    const glm::dvec3 model = TransmittanceOfRatios(params, ratios[i]);
    const glm::dvec3 scale = weighting.Scale(row);
    for (int c = 0; c < table.channels; ++c) {
      point.cost +=
          0.5 * Sqr(WeightedResidual(model[c], row.value[c], scale[c]));
    }
  }
  point.params = params;
  return point;
}

// The best point of a log grid over h (plus the init), and the best one at
// least a factor 2 away from it (another basin), as starts.
std::vector<std::vector<double>> SearchStarts(
    const MeasurementTable& table, const Weighting& weighting,
    const HolesTile& tile, const std::vector<ParameterSpec>& specs,
    const HolesParams& init) {
  std::vector<GridPoint> points;
  if (specs[0].free) {
    for (double h = specs[0].lower * 1.5; h < specs[0].upper;
         h *= std::pow(2.0, 0.25)) {
      HolesParams p = init;
      p.thickness_texels = h;
      points.push_back(EvaluateStart(table, weighting, tile, specs, p));
    }
  }
  points.push_back(EvaluateStart(table, weighting, tile, specs, init));
  std::sort(
      points.begin(), points.end(),
      [](const GridPoint& a, const GridPoint& b) { return a.cost < b.cost; });
  std::vector<std::vector<double>> starts;
  const double best_h = points.front().params.thickness_texels;
  for (const GridPoint& p : points) {
    const bool first = starts.empty();
    if (!first && std::abs(std::log(p.params.thickness_texels / best_h)) <
                      std::log(2.0)) {
      continue;
    }
    std::vector<double> x(FlatSize(p.params));
    ToArray(p.params, x.data());
    starts.push_back(x);
    if (starts.size() == 2) break;
  }
  return starts;
}

}  // namespace

HolesFitResult FitHoles(const MeasurementTable& table, const HolesTile& tile,
                        const HolesFitOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  RequireWeightedRows(table);
  if (table.quantity != Quantity::kTransmittance) {
    throw InputError(std::string("a holes model predicts transmittance; the "
                                 "table holds ") +
                     QuantityName(table.quantity));
  }
  const HolesParams init = options.init ? *options.init : HolesParams();
  const std::string invalid = ValidateParams(init);
  if (!invalid.empty()) throw InputError("initial parameters: " + invalid);

  LeastSquaresProblem lsq;
  lsq.specs = HolesSpecs(options.fit_wall_color);
  ApplyFreeFix(options.fix, options.free_only, &lsq.specs);
  if (table.channels == 1) {  // one channel: wall_color_g, _b follow r
    lsq.specs[2].free = lsq.specs[3].free = false;
  }
  lsq.block_sizes = {FlatSize(init)};
  const Weighting weighting(table, options.solver.noise);
  lsq.sigma_known = weighting.LevelKnown();
  ResidualBlocks blocks;
  blocks.used = {0};
  SetModelResiduals(
      std::make_shared<const HolesEvaluator>(HolesEvaluator{&table, &tile}),
      TableFitRows(table, weighting), blocks, &lsq);

  const std::vector<std::vector<double>> starts =
      SearchStarts(table, weighting, tile, lsq.specs, init);
  HolesFitResult result;
  std::vector<double> x = starts.front();
  result.report = SolveLeastSquares(lsq, starts, options.solver, &x);
  ReportWeighting(weighting, &result.report);
  FromArray(x.data(), &result.params);
  result.report.rows = static_cast<int>(table.rows.size());
  if (table.channels == 1) {  // one channel: one wall colour
    result.params.wall_color =
        OneChannelRgb("wall_color", result.params.wall_color, &result.report);
  }
  result.report.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0)
          .count();
  return result;
}

}  // namespace clothfit
