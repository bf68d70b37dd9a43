// The pieces of SolveLeastSquares (fitting/least_squares.cc) that its
// report (fitting/least_squares_report.cc) shares: a problem built at x,
// and the report of a solution. Includes Ceres: for fitting/*.cc only
// (not installed).
#pragma once

#include <ceres/ceres.h>

#include <algorithm>
#include <memory>
#include <thread>
#include <vector>

#include "fitting/least_squares.h"

namespace clothfit {

// The problem at x, with bounds and free/fixed entries applied.
struct BuiltProblem {
  std::unique_ptr<ceres::LossFunction> loss;
  std::unique_ptr<ceres::Problem> problem;
  std::vector<double*> blocks;
  size_t residuals = 0;  // of the rows (LeastSquaresProblem::add_residuals)
};

// The threads of the residuals' evaluation (0: every core).
inline int Threads(const SolverOptions& options) {
  return options.num_threads > 0
             ? options.num_threads
             : std::max(1,
                        static_cast<int>(std::thread::hardware_concurrency()));
}

// The problem of `which` rows at x (whose storage the blocks point into),
// with the specs' bounds and free/fixed entries applied.
void Build(const LeastSquaresProblem& lsq, const SolverOptions& options,
           std::vector<double>* x, BuiltProblem* out,
           const ResidualRows& which = ResidualRows());

// Standard deviations from the Jacobian of the free parameters at the
// solution x of `built` (fitting/covariance_internal.h), the parameters the
// data cannot determine named instead, and each parameter's entry
// (bounds, search limits) in report->parameters.
void Report(const LeastSquaresProblem& lsq, const SolverOptions& options,
            const std::vector<double>& x, BuiltProblem* built,
            FitReport* report);

}  // namespace clothfit
