#include "fitting/thread_fit.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>

#include "fitting/energy_bound_fit_internal.h"
#include "fitting/least_squares.h"
#include "fitting/model_residual_internal.h"
#include "fitting/start_search.h"
#include "io/input_error.h"
#include "models/evaluate.h"

namespace clothfit {
namespace {

// The thread's value at row i of a thread table: block 0 holds the thread
// parameters (models/params.h ToArray order).
// Times the row's energy bound factor, when the fit has them.
struct ThreadEvaluator {
  const MeasurementTable* table;
  const std::vector<double>* bound_factor;

  template <typename T>
  Vec3<T> operator()(const T* const* blocks, size_t i) const {
    ThreadParamsT<T> p;
    FromArray(blocks[0], &p);
    const TableRow& row = table->rows[i];
    const Vec3<T> v = Value(p, row.wi, row.wo, table->quantity);
    return bound_factor ? v * T((*bound_factor)[i]) : v;
  }

  // The paper's thread at the blocks, rho(wi, wo) cosine-weighted without
  // the scale: what the energy bound is a quadrature of.
  template <typename T>
  auto BoundRho(const T* const* blocks) const {
    ThreadParamsT<T> p;
    FromArray(blocks[0], &p);
    return [p](const glm::dvec3& wi, const glm::dvec3& wo) {
      return Rho(p, wi, wo);
    };
  }
};

// Starts: a grid search over the widths (and eta) with the linear
// parameters (albedo, kd, scale) solved in closed form; the init's values
// join the grid, fixed entries keep them (fitting/start_search.h). The
// search sees the rows the starts are solved on.
std::vector<std::vector<double>> SearchThreadStarts(
    const MeasurementTable& table, const ThreadFitOptions& options,
    const Weighting& weighting, const std::vector<ParameterSpec>& specs,
    const std::vector<double>* bound_factor, const EnergyBound* search_bound) {
  MeasurementTable sample_storage;
  const MeasurementTable& sample = SearchTable(table, &sample_storage);
  const std::vector<double> factor =
      search_bound ? EnergyBoundFactors(sample, search_bound)
                   : SearchRowValues(table.rows.size(), bound_factor);
  StartSearchProblem search;
  search.table = &sample;
  search.weighting = &weighting;
  search.init = {options.init ? *options.init : ThreadParams()};
  search.contribution = [&](size_t, const ThreadParams& p) {
    RowValues v(sample.rows.size());
    for (size_t i = 0; i < v.size(); ++i) {
      v[i] = Value(p, sample.rows[i].wi, sample.rows[i].wo, sample.quantity);
      if (!factor.empty()) v[i] *= factor[i];
    }
    return v;
  };
  search.kd_free = {specs[1].free};
  search.gamma_s_free = {specs[2].free};
  search.gamma_v_free = {specs[3].free};
  search.albedo_free = {specs[4].free || specs[5].free || specs[6].free};
  search.fit_scale = options.fit_scale;
  std::vector<std::vector<double>> starts;
  for (const StartPoint& point :
       SearchStarts(search, std::max(1, options.solve_starts))) {
    std::vector<double> x(kThreadFlatSize + 1);
    ToArray(point.threads[0], x.data());
    x[kThreadFlatSize] = point.scale;
    starts.push_back(x);
  }
  return starts;
}

// One fit of the model through the rows' fixed bound factors (null: the
// paper's model), or (`plan`) of the bounded model with its tables through
// that plan: from the start search, from `refit_from` alone, or from both
// when `search_bound` is given (whose factors of the rows the search
// sees); a fitted scale at most scale_cap.
ThreadFitResult FitThreadThrough(const MeasurementTable& table,
                                 const ThreadFitOptions& options,
                                 const std::vector<double>* bound_factor,
                                 const ThreadParams* refit_from,
                                 const EnergyBoundPlan* plan = nullptr,
                                 const EnergyBound* search_bound = nullptr,
                                 double scale_cap = HUGE_VAL) {
  LeastSquaresProblem lsq;
  lsq.specs = ParameterSpecs(ThreadParams());
  ApplyFreeFix(options.fix, options.free_only, &lsq.specs);
  if (table.channels == 1) {  // one channel: albedo_g, albedo_b follow r
    lsq.specs[5].free = lsq.specs[6].free = false;
  }
  lsq.block_sizes = {kThreadFlatSize, 1};
  lsq.specs.push_back(SpecOf(kFitScale, kFitScale.name));
  lsq.specs.back().free = options.fit_scale;
  lsq.specs.back().upper = std::min(lsq.specs.back().upper, scale_cap);
  const Weighting weighting(table, options.solver.noise);
  lsq.sigma_known = weighting.LevelKnown();
  ResidualBlocks blocks;
  blocks.used = {0};
  if (options.fit_scale) {
    blocks.used.push_back(1);
    blocks.scale = 1;
  }
  SetModelResiduals(std::make_shared<const ThreadEvaluator>(
                        ThreadEvaluator{&table, bound_factor}),
                    TableFitRows(table, weighting), blocks, &lsq, plan);
  std::vector<std::vector<double>> starts;
  if (!refit_from || search_bound) {
    starts = SearchThreadStarts(table, options, weighting, lsq.specs,
                                bound_factor, search_bound);
  }
  if (refit_from) {
    std::vector<double> x(kThreadFlatSize + 1);
    ToArray(*refit_from, x.data());
    x[kThreadFlatSize] = refit_from->scale;
    starts.insert(starts.begin(), x);
  }

  ThreadFitResult result;
  std::vector<double> x = starts.front();
  result.report = SolveLeastSquares(lsq, starts, options.solver, &x);
  ReportWeighting(weighting, &result.report);
  FromArray(x.data(), &result.params);
  result.params.scale = x[kThreadFlatSize];  // 1 unless fitted
  result.report.rows = static_cast<int>(table.rows.size());
  if (table.channels == 1) {  // one channel: one albedo
    result.params.albedo =
        OneChannelRgb("albedo", result.params.albedo, &result.report);
  }
  return result;
}

}  // namespace

ThreadFitResult FitThread(const MeasurementTable& table,
                          const ThreadFitOptions& given) {
  // The search and the solves fit the paper's model (the bound, if any, is
  // the fit's to find): an init's bound is dropped.
  ThreadFitOptions options = given;
  if (options.init) options.init->energy_bound = nullptr;
  const auto t0 = std::chrono::steady_clock::now();  // search + solves
  RequireWeightedRows(table);
  if (table.quantity == Quantity::kTransmittance) {
    throw InputError(
        "a thread model predicts brdf or cosine_weighted "
        "values, not transmittance");
  }
  ThreadFitResult result;
  if (options.energy_bound) {
    result = SettleEnergyBound<ThreadParams>(
        table,
        [&](const EnergyBoundPlan& plan, const ThreadParams& from,
            const EnergyBound* search_bound, double scale_cap) {
          return FitThreadThrough(table, options, nullptr, &from, &plan,
                                  search_bound, scale_cap);
        },
        ChooseBoundedStart<ThreadParams>(
            table, options.solver.noise,
            [&](const MeasurementTable& rows, bool) {
              return FitThreadThrough(rows, options, nullptr, nullptr);
            }));
  } else {
    // The init's bound held: its factors fixed, and carried by the result.
    const auto bound = given.init ? given.init->energy_bound : nullptr;
    const std::vector<double> factors =
        bound ? EnergyBoundFactors(table, bound.get()) : std::vector<double>();
    result =
        FitThreadThrough(table, options, bound ? &factors : nullptr, nullptr);
    result.params.energy_bound = bound;
  }
  result.report.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0)
          .count();
  return result;
}

}  // namespace clothfit
