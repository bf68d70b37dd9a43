// The linear solver of the Levenberg-Marquardt steps: a knob of
// every fit, swept by `clothfit bench`. Our own enum, mapped to Ceres by
// fitting/ceres_linear_solver_internal.h, so that Ceres stays out of the
// public headers.
// Only the solvers that make sense for the fits' small dense problems (at
// most a few dozen parameters, thousands of residuals): Ceres' dense QR of
// the Jacobian and dense Cholesky of the normal equations, each with
// Eigen or LAPACK (Ceres' dense_linear_algebra_library_type). Ceres has no
// SVD linear solver (its SVD is only for covariances); the sparse and
// Schur solvers are for large problems with structure these do not have.
#pragma once

#include <string>
#include <vector>

namespace clothfit {

enum class LinearSolver {
  kDenseQr,                    // "dense_qr": QR of J (Eigen)
  kDenseNormalCholesky,        // "dense_normal_cholesky": LDLT of J^T J
  kDenseQrLapack,              // "dense_qr_lapack": QR of J (LAPACK)
  kDenseNormalCholeskyLapack,  // "dense_normal_cholesky_lapack"
};

// The command-line name ("dense_qr", ...).
std::string LinearSolverName(LinearSolver solver);

// Every solver, in the enum's order.
std::vector<LinearSolver> AllLinearSolvers();

// Parses a command-line name; false for an unknown one.
bool ParseLinearSolver(const std::string& name, LinearSolver* solver);

// The names, comma-separated, for messages and --help.
std::string LinearSolverNames();

}  // namespace clothfit
