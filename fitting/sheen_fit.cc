#include "fitting/sheen_fit.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <utility>

#include "fitting/least_squares.h"
#include "fitting/model_residual_internal.h"
#include "io/input_error.h"
#include "models/evaluate.h"

namespace clothfit {
namespace {

// The material's value at row i: block 0 holds its flat parameters.
struct SheenEvaluator {
  const MeasurementTable* table;

  template <typename T>
  Vec3<T> operator()(const T* const* blocks, size_t i) const {
    SheenParamsT<T> p;
    FromArray(blocks[0], &p);
    const TableRow& row = table->rows[i];
    return Value(p, row.wi, row.wo, table->quantity);
  }
};

// The grid of starts: the two roughnesses on a 4 x 4 grid (the init's
// values included), the colours of the init; fixed entries keep the
// init's values. Ranked by the weighted cost at the start.
std::vector<std::vector<double>> RankedStarts(const LeastSquaresProblem& lsq,
                                              const SheenParams& init,
                                              const MeasurementTable& table,
                                              const Weighting& weighting) {
  constexpr int kRoughness = 3, kSheenRoughness = 7;  // flat positions
  std::vector<double> base(FlatSize(init));
  ToArray(init, base.data());
  std::vector<std::vector<double>> starts = {base};
  for (double r : {0.25, 0.5, 0.75, 1.0}) {
    for (double rs : {0.2, 0.4, 0.6, 0.9}) {
      std::vector<double> x = base;
      if (lsq.specs[kRoughness].free) x[kRoughness] = r;
      if (lsq.specs[kSheenRoughness].free) x[kSheenRoughness] = rs;
      if (x != base) starts.push_back(x);
    }
  }
  std::vector<std::pair<double, size_t>> cost;
  for (size_t k = 0; k < starts.size(); ++k) {
    SheenParams p;
    FromArray(starts[k].data(), &p);
    double sum = 0.0;
    for (const TableRow& row : table.rows) {
      const glm::dvec3 m = Value(p, row.wi, row.wo, table.quantity);
      const glm::dvec3 scale = weighting.Scale(row);
      for (int c = 0; c < table.channels; ++c) {
        sum += Sqr((m[c] - row.value[c]) * scale[c]);
      }
    }
    cost.emplace_back(std::isfinite(sum) ? sum : HUGE_VAL, k);
  }
  std::stable_sort(cost.begin(), cost.end());
  std::vector<std::vector<double>> ranked;
  for (const auto& entry : cost) ranked.push_back(starts[entry.second]);
  return ranked;
}

}  // namespace

SheenFitResult FitSheen(const MeasurementTable& table,
                        const SheenFitOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  RequireWeightedRows(table);
  if (table.quantity == Quantity::kTransmittance) {
    throw InputError(
        "a sheen model predicts brdf or cosine_weighted values, not "
        "transmittance");
  }
  const SheenParams init = options.init ? *options.init : SheenParams();
  LeastSquaresProblem lsq;
  lsq.specs = ParameterSpecs(init);
  ApplyFreeFix(options.fix, options.free_only, &lsq.specs);
  if (table.channels == 1) {  // one channel: g and b follow r
    for (int k : {1, 2, 5, 6}) lsq.specs[k].free = false;
  }
  lsq.block_sizes = {static_cast<int>(FlatSize(init))};
  const Weighting weighting(table, options.solver.noise);
  lsq.sigma_known = weighting.LevelKnown();
  lsq.stop_after_hits = std::max(1, options.solve_starts);
  ResidualBlocks blocks;
  blocks.used = {0};
  SetModelResiduals(
      std::make_shared<const SheenEvaluator>(SheenEvaluator{&table}),
      TableFitRows(table, weighting), blocks, &lsq);

  SheenFitResult result;
  const std::vector<std::vector<double>> starts =
      RankedStarts(lsq, init, table, weighting);
  std::vector<double> x = starts.front();
  result.report = SolveLeastSquares(lsq, starts, options.solver, &x);
  ReportWeighting(weighting, &result.report);
  FromArray(x.data(), &result.params);
  result.report.rows = static_cast<int>(table.rows.size());
  if (table.channels == 1) {
    result.params.base_color =
        OneChannelRgb("base_color", result.params.base_color, &result.report);
    result.params.sheen_color =
        OneChannelRgb("sheen_color", result.params.sheen_color, &result.report);
  }
  result.report.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0)
          .count();
  return result;
}

}  // namespace clothfit
