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

}  // namespace clothfit
