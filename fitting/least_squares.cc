#include "fitting/least_squares.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <sstream>
#include <utility>

#include "fitting/ceres_linear_solver_internal.h"
#include "fitting/least_squares_internal.h"

namespace clothfit {
namespace {

std::unique_ptr<ceres::LossFunction> MakeLoss(const SolverOptions& options) {
  switch (options.loss) {
    case Loss::kHuber:
      return std::make_unique<ceres::HuberLoss>(options.loss_scale);
    case Loss::kCauchy:
      return std::make_unique<ceres::CauchyLoss>(options.loss_scale);
    case Loss::kNone:
      break;
  }
  return nullptr;
}

}  // namespace

void Build(const LeastSquaresProblem& lsq, const SolverOptions& options,
           std::vector<double>* x, BuiltProblem* out,
           const ResidualRows& which) {
  out->loss = MakeLoss(options);
  ceres::Problem::Options problem_options;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  out->problem = std::make_unique<ceres::Problem>(problem_options);
  out->blocks.clear();
  int offset = 0;
  for (int size : lsq.block_sizes) {
    out->blocks.push_back(x->data() + offset);
    offset += size;
  }
  out->residuals = lsq.add_residuals(out->blocks, out->loss.get(),
                                     out->problem.get(), which);
  offset = 0;
  for (size_t b = 0; b < lsq.block_sizes.size(); ++b) {
    const int size = lsq.block_sizes[b];
    double* block = out->blocks[b];
    if (!out->problem->HasParameterBlock(block)) {
      offset += size;
      continue;
    }
    std::vector<int> fixed;
    for (int i = 0; i < size; ++i) {
      const ParameterSpec& spec = lsq.specs[offset + i];
      if (spec.free) {
        out->problem->SetParameterLowerBound(block, i, spec.lower);
        out->problem->SetParameterUpperBound(block, i, spec.upper);
      } else {
        fixed.push_back(i);
      }
    }
    if (static_cast<int>(fixed.size()) == size) {
      out->problem->SetParameterBlockConstant(block);
    } else if (!fixed.empty()) {
      out->problem->SetManifold(block, new ceres::SubsetManifold(size, fixed));
    }
    offset += size;
  }
}

FitReport SolveLeastSquares(const LeastSquaresProblem& lsq,
                            const std::vector<std::vector<double>>& starts,
                            const SolverOptions& options,
                            std::vector<double>* x_out) {
  const auto t0 = std::chrono::steady_clock::now();
  FitReport best;
  best.final_cost = HUGE_VAL;
  std::vector<double> best_x;
  int total_iterations = 0;
  // The starts see a sample of the rows of a large problem.
  const bool sampled = lsq.rows > kSampleRows;
  std::vector<uint32_t> sample;
  if (sampled) sample = SampleRows(lsq.rows, kSampleRows);
  const ResidualRows start_rows{sampled ? &sample : nullptr, true};
  size_t solved_residuals = 0;  // of the last solve's rows
  // One solve from x (clamped into the bounds) on `which` rows, of at
  // most `iterations` (0: options.max_iterations); its summary.
  auto solve = [&](std::vector<double>* x, const ResidualRows& which,
                   int iterations = 0) {
    for (size_t i = 0; i < x->size(); ++i) {
      if (lsq.specs[i].free) {
        (*x)[i] =
            std::min(std::max((*x)[i], lsq.specs[i].lower), lsq.specs[i].upper);
      }
    }
    BuiltProblem built;
    Build(lsq, options, x, &built, which);
    solved_residuals = built.residuals;
    ceres::Solver::Options solver_options;
    SetCeresLinearSolver(options.linear_solver, &solver_options);
    solver_options.max_num_iterations =
        iterations > 0 ? iterations : options.max_iterations;
    solver_options.num_threads = Threads(options);
    solver_options.function_tolerance = 1e-6;
    solver_options.parameter_tolerance = 1e-10;
    solver_options.gradient_tolerance = 1e-14;
    ceres::Solver::Summary summary;
    ceres::Solve(solver_options, built.problem.get(), &summary);
    total_iterations += static_cast<int>(summary.iterations.size());
    return summary;
  };
  auto finite_x = [](const std::vector<double>& x) {
    for (double v : x) {
      if (!std::isfinite(v)) return false;
    }
    return true;
  };
  // A solve ended at a solution that can be used: Ceres says so and its
  // cost and parameters are finite.
  auto usable_solve = [&](const ceres::Solver::Summary& summary,
                          const std::vector<double>& x) {
    return summary.IsSolutionUsable() && std::isfinite(summary.final_cost) &&
           finite_x(x);
  };
  // A solve's outcome as the best so far.
  auto take = [&](const ceres::Solver::Summary& summary,
                  const std::vector<double>& x) {
    best.converged = summary.termination_type == ceres::CONVERGENCE;
    best.termination = ceres::TerminationTypeToString(summary.termination_type);
    best.message = summary.message;
    best.final_cost = summary.final_cost;
    best.residuals = static_cast<int>(solved_residuals);
    best_x = x;
  };
  // The stopping rule's count: solves whose cost is within kSameBasin of
  // the best.
  constexpr double kSameBasin = 1e-3;
  // Each solve's cost and whether it is plausible (lsq.plausible): a
  // plausible solution is kept over any other, and counted with its kind.
  std::vector<std::pair<double, bool>> costs;
  bool best_plausible = false;
  auto hits = [&] {
    return std::count_if(costs.begin(), costs.end(), [&](const auto& c) {
      return c.second == best_plausible &&
             c.first <= best.final_cost * (1.0 + kSameBasin) + 1e-300;
    });
  };
  // Screening: every start solved a few iterations, the best few of
  // those solutions (plausible first, then by cost) solved on; below,
  // `order` holds the starts the loop solves to convergence.
  const std::vector<std::vector<double>>* order = &starts;
  std::vector<std::vector<double>> screened;
  const bool screen = lsq.screen_keep > 0 && lsq.screen_iterations > 0 &&
                      starts.size() > static_cast<size_t>(lsq.screen_keep);
  if (screen) {
    std::vector<std::pair<double, std::vector<double>>> ranked;
    std::vector<std::vector<double>> unusable;  // their starts
    for (size_t s = 0; s < starts.size(); ++s) {
      if (options.progress) {
        options.progress("screening start " + std::to_string(s + 1) + " of " +
                         std::to_string(starts.size()));
      }
      std::vector<double> x = starts[s];
      const ceres::Solver::Summary summary =
          solve(&x, start_rows, lsq.screen_iterations);
      if (usable_solve(summary, x)) {
        ranked.emplace_back(summary.final_cost, std::move(x));
      } else {
        unusable.push_back(starts[s]);
      }
    }
    std::stable_sort(
        ranked.begin(), ranked.end(),
        [](const auto& a, const auto& b) { return a.first < b.first; });
    // Plausibility is checked lowest cost first, until enough are found
    // (the check is a quadrature, fitting/energy.h).
    const size_t keep = static_cast<size_t>(lsq.screen_keep);
    std::vector<std::vector<double>> implausible;
    for (auto& [cost, x] : ranked) {
      if (screened.size() == keep) break;
      if (!lsq.plausible || lsq.plausible(x)) {
        screened.push_back(std::move(x));
      } else {
        implausible.push_back(std::move(x));
      }
    }
    for (auto& x : implausible) {
      if (screened.size() < keep) screened.push_back(std::move(x));
    }
    for (auto& x : unusable) {
      if (screened.size() < keep) screened.push_back(std::move(x));
    }
    order = &screened;
  }
  size_t solved = 0;
  for (size_t s = 0; s < order->size(); ++s) {
    if (lsq.stop_after_hits > 0 && best.usable &&
        hits() >= lsq.stop_after_hits) {
      break;
    }
    ++solved;
    if (options.progress) {
      options.progress("start " + std::to_string(s + 1) + " of " +
                       std::to_string(order->size()));
    }
    std::vector<double> x = (*order)[s];
    const ceres::Solver::Summary summary = solve(&x, start_rows);
    const bool finite = std::isfinite(summary.final_cost) && finite_x(x);
    const bool usable = summary.IsSolutionUsable() && finite;
    const bool plausible = usable && (!lsq.plausible || lsq.plausible(x));
    if (usable) costs.emplace_back(summary.final_cost, plausible);
    const bool better = usable && (plausible != best_plausible
                                       ? plausible
                                       : summary.final_cost < best.final_cost);
    if (better) {
      best_plausible = plausible;
      best = FitReport();
      best.usable = true;
      take(summary, x);
    } else if (!best.usable && best_x.empty()) {
      best.termination =
          ceres::TerminationTypeToString(summary.termination_type);
      // A model value that is not finite is named with its row,
      // at the start when the solver could not leave it.
      std::string where = NonFiniteRow(lsq, x);
      if (where.empty() && x != (*order)[s])
        where = NonFiniteRow(lsq, (*order)[s]);
      if (!where.empty()) {
        best.message = where + " (solver: " + summary.message + ")";
      } else {
        best.message =
            finite ? summary.message
                   : "non-finite cost or parameters: " + summary.message;
      }
    }
  }
  const long reached = best.usable ? hits() : 0;  // before reweighting
  // Weights that depend on the model (relative noise): solve again with
  // the weights of the best solution until they settle (iteratively
  // reweighted least squares; a pass changes x by O(F) of its first
  // change, so two or three passes reach the solver's precision).
  auto reweight_passes = [&](const ResidualRows& which) {
    if (!lsq.reweight || best_x.empty()) return;
    for (int pass = 0; pass < 3; ++pass) {
      lsq.reweight(best_x);
      std::vector<double> x = best_x;
      const ceres::Solver::Summary summary = solve(&x, which);
      if (!usable_solve(summary, x)) {
        break;  // keep the last usable solution (its weights differ a little)
      }
      double change = 0.0;
      for (size_t i = 0; i < x.size(); ++i) {
        const double span = lsq.specs[i].upper - lsq.specs[i].lower;
        const double scale = std::isfinite(span) && span > 0.0
                                 ? std::min(span, std::abs(best_x[i]) + 1e-12)
                                 : std::abs(best_x[i]) + 1e-12;
        change = std::max(change, std::abs(x[i] - best_x[i]) / scale);
      }
      take(summary, x);
      if (change < 1e-9) break;
    }
  };
  reweight_passes(start_rows);
  // A sample's best, refined on every row: few iterations from there.
  if (sampled && best.usable) {
    if (options.progress) {
      options.progress("refining on all " + std::to_string(lsq.rows) + " rows");
    }
    std::vector<double> x = best_x;
    const ceres::Solver::Summary summary = solve(&x, ResidualRows());
    if (usable_solve(summary, x)) {
      take(summary, x);
      reweight_passes(ResidualRows());
    } else {
      best.usable = best.converged = false;
      best.message = "the solve on every row failed after the sample's (" +
                     summary.message + ")";
    }
  }
  best.starts = static_cast<int>(solved);
  if (lsq.stop_after_hits > 0) {
    std::ostringstream rule;
    if (screen) {
      rule << starts.size() << " starts screened (at most "
           << lsq.screen_iterations << " iterations each), the best "
           << order->size() << " solved on; ";
    }
    rule << solved << " of " << order->size()
         << " starts solved; the best cost was reached " << reached
         << " time(s)"
         << (reached >= lsq.stop_after_hits
                 ? " (the rule: stop at " +
                       std::to_string(lsq.stop_after_hits) + ")"
                 : ", fewer than the " + std::to_string(lsq.stop_after_hits) +
                       " the rule asks: more starts may find a lower cost");
    best.search = rule.str();
  }
  best.iterations = total_iterations;
  if (!best_x.empty()) {
    // The covariance is that of the problem solved, robust loss included.
    BuiltProblem built;
    std::vector<double> x = best_x;
    Build(lsq, options, &x, &built);
    Report(lsq, options, x, &built, &best);
    // A free parameter on a search limit: the solver wanted to leave the
    // region where the model means something; not a converged fit.
    // Fewer residuals than free parameters: any solution is one of many.
    const int free_count = static_cast<int>(
        std::count_if(best.parameters.begin(), best.parameters.end(),
                      [](const ParameterReport& p) { return p.free; }));
    const int distinct = DistinctResiduals(lsq, x, best.residuals, free_count);
    if (best.converged && distinct < free_count) {
      best.converged = false;
      best.message =
          (distinct < best.residuals
               ? std::to_string(best.residuals) + " residual(s) at " +
                     std::to_string(distinct) + " distinct one(s)"
               : std::to_string(best.residuals) + " residual(s)") +
          " cannot determine " + std::to_string(free_count) +
          " free parameters (give more rows, or fix some with --fix)";
    }
    // A free parameter on a search limit that changes no residual there
    // (ParameterReport::no_effect) is undetermined, not pushing outward:
    // it is named as not identifiable and does not stop convergence.
    for (const ParameterReport& p : best.parameters) {
      if (!p.at_search_limit || p.no_effect || !best.converged) continue;
      best.converged = false;
      std::ostringstream msg;
      msg << p.name << " stopped at its search limit " << p.value
          << " (a local minimum or a model that does not fit; try --init or "
             "--fix)";
      best.message = msg.str();
    }
    double se = 0.0, ss = 0.0;
    size_t pairs = 0;
    lsq.predict(x, [&](double model, double measured, const TableRow*) {
      se += (model - measured) * (model - measured);
      ss += measured * measured;
      ++pairs;
    });
    const double n = std::max<size_t>(1, pairs);
    best.rms = std::sqrt(se / n);
    best.relative_rms = ss > 0.0 ? std::sqrt(se / ss) : 0.0;
    *x_out = x;
  }
  best.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0)
          .count();
  return best;
}

}  // namespace clothfit
