#include "fitting/linear_solver.h"

#include <ceres/types.h>

#include "fitting/ceres_linear_solver_internal.h"

namespace clothfit {
namespace {

struct Entry {
  LinearSolver solver;
  const char* name;
  ceres::LinearSolverType type;
  bool lapack;
};

constexpr Entry kEntries[] = {
    {LinearSolver::kDenseQr, "dense_qr", ceres::DENSE_QR, false},
    {LinearSolver::kDenseNormalCholesky, "dense_normal_cholesky",
     ceres::DENSE_NORMAL_CHOLESKY, false},
    {LinearSolver::kDenseQrLapack, "dense_qr_lapack", ceres::DENSE_QR, true},
    {LinearSolver::kDenseNormalCholeskyLapack, "dense_normal_cholesky_lapack",
     ceres::DENSE_NORMAL_CHOLESKY, true},
};

const Entry& Find(LinearSolver solver) {
  for (const Entry& e : kEntries) {
    if (e.solver == solver) return e;
  }
  return kEntries[0];
}

}  // namespace

std::string LinearSolverName(LinearSolver solver) { return Find(solver).name; }

std::vector<LinearSolver> AllLinearSolvers() {
  std::vector<LinearSolver> all;
  for (const Entry& e : kEntries) all.push_back(e.solver);
  return all;
}

bool ParseLinearSolver(const std::string& name, LinearSolver* solver) {
  for (const Entry& e : kEntries) {
    if (name == e.name) {
      *solver = e.solver;
      return true;
    }
  }
  return false;
}

std::string LinearSolverNames() {
  std::string names;
  for (const Entry& e : kEntries) {
    names += (names.empty() ? "" : ", ") + std::string(e.name);
  }
  return names;
}

void SetCeresLinearSolver(LinearSolver solver,
                          ceres::Solver::Options* options) {
  const Entry& e = Find(solver);
  options->linear_solver_type = e.type;
  options->dense_linear_algebra_library_type =
      e.lapack ? ceres::LAPACK : ceres::EIGEN;
}

}  // namespace clothfit
