// Ceres' side of fitting/linear_solver.h, for fitting/*.cc only: it
// includes Ceres, so it is not installed (cmake/install.cmake leaves out
// *_internal.h) and no public header includes it.
#pragma once

#include <ceres/solver.h>

#include "fitting/linear_solver.h"

namespace clothfit {

// Sets the linear solver type and the dense linear algebra library
// (Eigen or LAPACK) of `options` for `solver`.
void SetCeresLinearSolver(LinearSolver solver, ceres::Solver::Options* options);

// Box bounds without Ceres' projected line search. By default a
// bound-constrained trust-region solve searches along every projected
// step, evaluating the Jacobian several times per iteration (82 times in
// 19 iterations on a gonio texel's joint solve); without it the step is
// still projected onto the box (Ceres' ParameterBlock::Plus). For solves
// that start next to their solution (the Lafortune refinements and joint
// solve): measured on an 8 x 8 gonio mip map (85 fits, one thread,
// docs/lafortune.md) 1.6x faster for a 0.3 % lower mean level-0 error.
// From far starts the line search steadies the steps and is kept.
inline void SkipProjectedLineSearch(ceres::Solver::Options* options) {
  options->max_num_line_search_step_size_iterations = 0;
}

}  // namespace clothfit
