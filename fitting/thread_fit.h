// Fits the thread BSDF (Sadeghi et al. 2013 eq. 2-4) to a thread table
// (thread frame: tangent +x, normal +z; SPEC §2): eta, kd, gamma_s_deg,
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
  // Start from here (one start); without it, the multi-start grid `grid`,
  // or DefaultThreadStarts() when that is empty.
  std::optional<ThreadParams> init;
  std::vector<ThreadParams> grid;
  // Parameter names (ThreadParamNames(), or "albedo" for all three) held
  // at their initial value; `free_only`, when not empty, frees only these.
  std::vector<std::string> fix;
  std::vector<std::string> free_only;
  // Multi-start: how many of the grid's best starts the solver runs from.
  int solve_starts = 2;
  // Data on an arbitrary scale: fit a factor s on the model as well
  // (reported as the parameter "scale"; the parameter file holds the model).
  bool fit_scale = false;
};

struct ThreadFitResult {
  ThreadParams params;
  FitReport report;
};

// Default start grid (used without an init): gamma_s_deg in {2, 6, 15},
// gamma_v_deg = 2 gamma_s_deg, kd in {0.1, 0.5}, eta 1.45; albedo per start
// solved in closed form (the model is linear in it). Starts are ranked by
// cost and the solver runs from the best `solve_starts`.
std::vector<ThreadParams> DefaultThreadStarts();

// Throws InputError for tables a thread cannot explain (transmittance) and
// for unknown parameter names in fix/free_only.
ThreadFitResult FitThread(const MeasurementTable& table,
                          const ThreadFitOptions& options);

}  // namespace clothfit
