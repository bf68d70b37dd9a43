// Starting points for the thread and cloth fits, found by a grid search
// that uses the structure of the microcylinder model instead of the solver.
//
// Each thread j adds a contribution c_j(p) to every row's model value, and
// c_j is linear in the albedo A and in B = A kd (eq. 4):
//   c_j = surface_j(gamma_s) + A P_j(gamma_v) + B (R_j - P_j)
// with surface = c_j(A = 0), P = c_j(A = 1, kd = 0) - surface and R =
// c_j(A = 1, kd = 1) - surface (R depends on neither width; eta stays at
// its initial value). So for given widths per thread the best albedos, kd
// and scale follow from a small non-negative least-squares problem. The
// basis vectors (one surface per gamma_s and one P per gamma_v of the grid,
// and R) are evaluated once, and their weighted inner products make every
// such problem independent of the number of rows. Coordinate descent over
// the threads picks each thread's grid point with the others held; the
// best distinct results are the starts for Ceres.
#pragma once

#include <functional>
#include <vector>

#include "fitting/residual_weight.h"
#include "io/table.h"
#include "models/microcylinder_thread.h"

namespace clothfit {

using RowValues = std::vector<glm::dvec3>;  // model value per row, rgb

struct StartSearchProblem {
  const MeasurementTable* table = nullptr;
  const Weighting* weighting = nullptr;  // of the table's rows
  // Thread j's contribution to each row's model value with parameters p.
  std::function<RowValues(size_t j, const ThreadParams& p)> contribution;
  std::vector<ThreadParams> init;  // per thread; fixed entries keep these
  // Per thread: which of kd, gamma_s_deg, gamma_v_deg, albedo are free
  // (eta stays at its initial value in the search).
  std::vector<bool> kd_free, gamma_s_free, gamma_v_free, albedo_free;
  bool shared_albedo = false;  // one albedo for every thread
  bool fit_scale = false;      // a free factor on the whole model
  // A Lambertian term (the cloth's diffuse, models/microcylinder_cloth.h):
  // its value per row for diffuse 1 (empty: no such term), and its
  // amplitude: solved with the other linear entries when free (in [0, 1]),
  // else init_diffuse.
  RowValues diffuse_basis;
  bool diffuse_free = false;
  glm::dvec3 init_diffuse{0.0};
};

struct StartPoint {
  std::vector<ThreadParams> threads;
  double scale = 1.0;
  glm::dvec3 diffuse{0.0};  // StartSearchProblem::diffuse_basis's amplitude
  double cost = 0.0;        // sum of squared weighted residuals
};

// The rows SolveLeastSquares solves the starts on (SampleRows,
// fitting/least_squares.h) as a table of their own, for the search:
// `table` itself when it has no more than kSampleRows rows (then *storage
// is untouched).
const MeasurementTable& SearchTable(const MeasurementTable& table,
                                    MeasurementTable* storage);

// The entries of `per_row` (one per row of a table of `rows` rows) at the
// rows SearchTable keeps; empty for a null `per_row`.
std::vector<double> SearchRowValues(size_t rows,
                                    const std::vector<double>* per_row);

// The `keep` best distinct starting points (some width a factor of 2 or
// more apart from every better one), best first. Grid: widths 1, 1.41, 2,
// 2.83, ..., 90 degrees (a factor sqrt(2) apart) and the initial value,
// for free widths.
std::vector<StartPoint> SearchStarts(const StartSearchProblem& problem,
                                     int keep);

}  // namespace clothfit
