// Fits the thread BSDF (Sadeghi et al. 2013 eq. 2-4) to a thread table
// (thread frame: tangent +x, normal +z; docs/formats.md): eta, kd, gamma_s_deg,
// gamma_v_deg and albedo (rgb; one value for one-channel tables).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "fitting/fit_result.h"
#include "io/table.h"
#include "models/microcylinder_thread.h"

namespace clothfit {

struct ThreadFitOptions {
  SolverOptions solver;
  // Starting values: they join the start search's grid, and fixed
  // parameters keep them (ThreadParams() defaults without an init).
  std::optional<ThreadParams> init;
  // Parameter names (the flat names of the thread's table: "eta", ...,
  // "albedo_r", or "albedo" for all three) held
  // at their initial value; `free_only`, when not empty, frees only these.
  std::vector<std::string> fix;
  std::vector<std::string> free_only;
  // Multi-start: the solver runs from this many of the best starts of the
  // grid search (fitting/start_search.h) and keeps the best result.
  int solve_starts = 2;
  // Data on an arbitrary scale: fit a factor s on the model as well
  // (reported as the parameter "scale"; the parameter file holds the model).
  bool fit_scale = false;
  // Fit the bounded model (fitting/energy_bound_fit_internal.h), the
  // default: the result carries its energy bound (models/bounded.h) and
  // conserves energy on both sides. Off: the paper's model (Sadeghi et al.
  // 2013), which exceeds albedo 1 toward grazing views along the thread,
  // or, when the init carries a bound, that bound held fixed (held-out
  // folds of a bounded fit).
  bool energy_bound = true;
};

using ThreadFitResult = FitResult<ThreadParams>;

// Throws InputError for tables a thread cannot explain (transmittance) and
// for unknown parameter names in fix/free_only.
ThreadFitResult FitThread(const MeasurementTable& table,
                          const ThreadFitOptions& options);

}  // namespace clothfit
