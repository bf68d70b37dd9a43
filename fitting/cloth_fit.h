// Fits the cloth patch (Sadeghi et al. 2013 eq. 5-13) to a reflection table:
// per thread albedo, kd, gamma_s_deg, gamma_v_deg by default (the paper's
// model); on request eta, the coverages (summing to at most 1), the
// tangent offsets (each, or a scale on all of a thread's keeping the
// weave's shape), the weave's rotation about the normal and a Lambertian
// term (models/microcylinder_cloth.h). The weave (threads, directions,
// number of tangent samples) comes from the initial parameters.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "fitting/fit_result.h"
#include "io/table.h"
#include "models/microcylinder_cloth.h"

namespace clothfit {

struct ClothFitOptions {
  SolverOptions solver;
  // Names as in the report: "threads[J].NAME" with NAME a flat name of the
  // thread's table ("kd", "albedo_r"), "albedo", "coverage" or
  // "offset_scale"; a bare NAME applies to every thread.
  std::vector<std::string> fix;
  std::vector<std::string> free_only;
  // Freed on top of the free set (the default one, or free_only): e.g.
  // the weave's freedoms "rotation_deg", "offsets_deg", "diffuse",
  // "coverage". `fix` wins over both.
  std::vector<std::string> also_free;
  // Multi-start around the initial parameters: each thread's two widths
  // scaled by 0.5, 1 or 2 (3^threads combinations), each with albedo and kd
  // solved in closed form (the model is linear in A and A kd); ranked by
  // cost, the solver runs from the best `solve_starts`.
  bool multi_start = true;
  int solve_starts = 2;
  // With the weave's geometry (rotation, offsets, offset_scale, coverage)
  // or eta free: the points of a space-filling design over them besides
  // the initial weave (fitting/cloth_search.h), and the multi-start's
  // stopping rule (stop once the best cost was reached this many times;
  // solve_starts is then the most starts, screened as below when more
  // than screen_keep).
  // 512: of 22 CUReT fits (11 fabrics, free coverages or eta), 4 solves
  // from 512 points ended lower than from 128 on 11, higher on 5, equal
  // on 6; 1024 and 2048 points did no better (docs/fitting.md).
  int design_points = 512;
  int stop_after_hits = 3;
  // With more design starts than screen_keep, each is first solved for at
  // most screen_iterations iterations and the best screen_keep solved on
  // (LeastSquaresProblem::screen_iterations). On CUReT (22 free-geometry
  // fits, docs/fitting.md) 8 starts screened by 20 iterations, the best 3
  // solved on, ended lower than 4 starts solved in full on 15 fits and
  // higher on 4 (by at most 0.0007 relative rms); against 8 solved in
  // full, lower on 9 and higher on 6, in about half their time.
  int screen_iterations = 20;
  int screen_keep = 3;
  // With the geometry fixed, a table of at most this many rows holds each
  // row's tangent samples (about 0.8 kB a row for the plain weave's four);
  // a larger one computes them each time the row is evaluated, with the
  // same result. Linen plain, default settings: 10^5 rows 3.6 s and 176
  // MiB held, 4.5 s and 103 MiB computed; 10^6 rows 24 s and 1035 MiB
  // held, 30 s and 303 MiB computed (docs/reliability.md).
  size_t held_sample_rows = 100000;
  // Every thread shares thread 0's albedo (one colour for the fabric).
  bool shared_albedo = false;
  // Data on an arbitrary scale: fit a factor s on the model as well
  // (reported as the parameter "scale"; the parameter file holds the model).
  bool fit_scale = false;
  // Energy conservation (fitting/energy.h, ConserveEnergyByScale): a
  // fitted model whose directional albedo exceeds 1 somewhere is scaled
  // down until it is 1 there, and the fit says so (not converged). Off
  // only for fits that are scored, not written (held-out folds).
  bool conserve_energy = true;
  // Fit the bounded model (fitting/energy_bound_fit_internal.h), the
  // default: the result carries its energy bound (models/bounded.h) and
  // conserves energy on both sides, with no scaling. Off: the paper's
  // model (Sadeghi et al. 2013), which does not conserve energy under
  // grazing light, or, when the init carries a bound, that bound held
  // fixed (held-out folds of a bounded fit).
  bool energy_bound = true;
};

using ClothFitResult = FitResult<ClothParams>;

// The default start for a weave whose threads are unknown: the weave's
// directions, coverages, tangent offsets and eta, with every thread at
// kd 0.3, gamma_s_deg 10, gamma_v_deg 20, albedo 0.1 (the fit then solves
// albedo and kd in closed form for each of its starts).
ClothParams GenericClothStart(const ClothParams& weave);

// Names of the free-able entries, in parameter-vector order.
std::vector<std::string> ClothParameterNames(const ClothParams& layout);
// Values of `c` in that order; offset_scale is the ratio of c's largest
// tangent offset to the layout's (1 when they are equal).
std::vector<double> ClothParameterValues(const ClothParams& c,
                                         const ClothParams& layout);

// `init` must pass ValidateClothParams and have 1 to 3 threads. Throws
// InputError for a transmittance table, more than 3 threads or unknown names.
ClothFitResult FitCloth(const MeasurementTable& table, const ClothParams& init,
                        const ClothFitOptions& options);

}  // namespace clothfit
