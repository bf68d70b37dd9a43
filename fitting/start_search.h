// Starting points for the thread and cloth fits, found by a grid search
// that uses the structure of the microcylinder model instead of the solver.
//
// Each thread j adds a contribution c_j(p) to every row's model value, and
// c_j is linear in the albedo A and in B = A kd (eq. 4):
//   c_j = surface_j(eta, gamma_s) + A P_j(eta, gamma_v) + B (R_j(eta) - P_j)
// with surface = c_j(A = 0), P = c_j(A = 1, kd = 0) - surface and R =
// c_j(A = 1, kd = 1) - surface (R does not depend on gamma_v). So for given
// (eta, gamma_s, gamma_v) per thread the best albedos, kd and scale follow
// from a small non-negative least-squares problem, and the grid over the
// widths needs only surface(gamma_s) and P(gamma_v) per grid value:
// a handful of model evaluations per thread, not one per grid point.
// Coordinate descent over the threads picks each thread's grid point with
// the others held; the best distinct results are the starts for Ceres.
#pragma once

#include <functional>
#include <vector>

#include "io/table.h"
#include "models/microcylinder_thread.h"

namespace clothfit {

using RowValues = std::vector<glm::dvec3>;  // model value per row, rgb

struct StartSearchProblem {
  const MeasurementTable* table = nullptr;
  // Thread j's contribution to each row's model value with parameters p.
  std::function<RowValues(size_t j, const ThreadParams& p)> contribution;
  std::vector<ThreadParams> init;  // per thread; fixed entries keep these
  // Per thread: which of eta, kd, gamma_s_deg, gamma_v_deg, albedo are free.
  std::vector<bool> eta_free, kd_free, gamma_s_free, gamma_v_free, albedo_free;
  bool shared_albedo = false;  // one albedo for every thread
  bool fit_scale = false;      // a free factor on the whole model
};

struct StartPoint {
  std::vector<ThreadParams> threads;
  double scale = 1.0;
  double cost = 0.0;  // sum of squared weighted residuals
};

// The `keep` best distinct starting points (some width a factor of 2 or
// more apart from every better one), best first. Grid: widths 1, 1.41, 2,
// 2.83, ..., 64 degrees (a factor sqrt(2) apart, and the initial value)
// when free; eta stays at its initial value (the solver refines it).
std::vector<StartPoint> SearchStarts(const StartSearchProblem& problem,
                                     int keep);

}  // namespace clothfit
