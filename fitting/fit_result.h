// What every fit reports, for every model (docs/formats.md "fit" object): cost,
// errors, iterations, time, termination, and per-parameter standard
// deviations, or an honest statement of which parameters the data cannot
// determine. One type, one JSON layout (FitReportJson).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "fitting/linear_solver.h"
#include "fitting/residual_weight.h"
#include "io/table.h"

namespace clothfit {

enum class Loss { kNone, kHuber, kCauchy };

// The limits of the solver options, the same for every fit.
inline constexpr int kMaxSolverIterations = 100000;
inline constexpr int kMaxSolverThreads = 256;

struct SolverOptions {
  // [1, kMaxSolverIterations]: per solve (each refit of a bounded thread
  // or cloth fit has it, fitting/energy_bound_fit_internal.h).
  int max_iterations = 200;
  Loss loss = Loss::kNone;
  double loss_scale = 1.0;  // > 0, in units of sigma (normalised residuals)
  // [0, kMaxSolverThreads]; 0: every core. The least-squares fits evaluate
  // residuals on them, a texel map fits texels on them.
  int num_threads = 1;
  // Of the Levenberg-Marquardt steps (fitting/linear_solver.h).
  LinearSolver linear_solver = LinearSolver::kDenseQr;
  // The noise model behind the residuals' weights
  // (fitting/residual_weight.h): by default the table's sigma, or relative
  // noise of an estimated level for a table without sigma.
  NoiseModel noise;
  // Told what a long fit is doing ("start 2 of 3", "candidate 4 of 12: ...");
  // may be empty.
  std::function<void(const std::string&)> progress;
};

// Whether `value` lies on the bound lower or upper of a fit (within 1e-9
// of the span): how every fit decides ParameterReport::at_bound.
inline bool OnFitBound(double value, double lower, double upper) {
  const double span = upper - lower > 1e-12 ? upper - lower : 1e-12;
  return value - lower < 1e-9 * span || upper - value < 1e-9 * span;
}

struct ParameterReport {
  std::string name;
  double value = 0.0;
  bool free = false;
  double stddev = -1.0;  // < 0: not available (fixed or not identifiable)
  // With the noise level estimated: the sandwich estimate, which needs no
  // noise model (least_squares.cc); < 0 otherwise.
  double stddev_sandwich = -1.0;
  double lower = 0.0, upper = 0.0;
  bool at_bound = false;         // a free parameter ended on its bound
  bool at_search_limit = false;  // ... on a bound that only limits the search
  // Free, and changes no residual at the solution (its Jacobian column is
  // zero next to the others): the data say nothing about it there.
  bool no_effect = false;
};

struct FitReport {
  bool usable = false;        // solver reached a usable solution
  bool converged = false;     // and met a convergence criterion
  std::string termination;    // Ceres termination type
  std::string message;        // Ceres message or the reason it is unusable
  double final_cost = 0.0;    // 1/2 sum of squared normalised residuals
  double rms = 0.0;           // RMS of (model - measured), data units
  double relative_rms = 0.0;  // RMS(model - measured) / RMS(measured)
  int iterations = 0;
  // Alternating fits (Lafortune: lobes, then the lookup table in closed
  // form): the passes, and the last mean relative change of the table; 0
  // for the others.
  int alternations = 0;
  double lut_change = 0.0;
  // The relative RMS error of each view's colour (Lafortune: the mean over
  // a view's rows of model and data, over the views; the view-dependent
  // colour of Daubert et al. 2001, Fig. 5); 0 where not computed.
  double view_relative_rms = 0.0;
  // Wall time of the whole fit: printed in the summary, never written to
  // the parameter file (same inputs give bit-identical files).
  double seconds = 0.0;
  int residuals = 0;
  int rows = 0;  // table rows fitted
  // The noise model the residuals were weighted with ("table", "relative",
  // "absolute"), its level F (given, or estimated from the residuals as
  // sqrt(2 cost / dof)) and its floor (relative).
  std::string noise_model;
  double noise_level = 0.0;
  bool noise_level_estimated = false;
  glm::dvec3 noise_floor{0.0};
  // What the solver minimised, in words ("relative error", "error",
  // "error in sigmas"), and its RMS over the residuals: sqrt(2 cost / m)
  // times a given level (relative: the RMS relative error; absolute: the
  // RMS error; table: the RMS in sigmas). relative_rms above is the data's
  // RMS(model - data) / RMS(data), the same for every noise model.
  std::string minimised;
  double minimised_rms = 0.0;
  // Table rows the model cannot explain, left out of the fit (a
  // reflection-only model's transmission rows); 0 for most fits.
  int rows_not_used = 0;
  int starts = 1;  // multi-start: how many solves were run
  // How the starts were found and why the multi-start ended, in words
  // ("" for a plain multi-start over every start).
  std::string search;
  // A lookup-table fit: the views with an entry of their own, of all.
  int lut_views_fitted = 0, lut_views = 0;
  // Of those, the views whose T was lowered to the energy bound (T times
  // the lobes' albedo at the view = 1, fitting/energy.h).
  int lut_views_at_energy_bound = 0;
  // A joint Lafortune solve whose optimum was not plausible (it had to be
  // scaled to conserve energy), replaced by the paper's alternation
  // (fitting/lafortune_fit.h).
  bool solve_fallback = false;
  // Free entries on a bound that only limits the search (also where the
  // parameters are not listed: a texel of a map).
  int at_search_limit = 0;
  // The white-furnace check of the fitted model (fitting/energy.h): its
  // largest directional albedo (< 0: not checked), where, and on which
  // side; energy_scale < 1: the fit's model reflected more than it
  // received and was scaled by that factor to conserve energy, which makes
  // the fit not converged.
  double max_albedo = -1.0;
  std::string max_albedo_at;  // DescribeEnergy
  // A thread or cloth fit without an energy bound: the light side, the
  // largest integral of f(wi, wo) wo.z over the views (EnergyCheck; of
  // what was written), which the paper's models do not keep below 1 at
  // grazing light; < 0: not checked apart (bounded, or another model).
  double max_light_albedo = -1.0;
  std::string max_light_albedo_at;
  double energy_scale = 1.0;
  // A thread or cloth fit of the bounded model (fitting/
  // energy_bound_fit_internal.h): what the bound did to the table's rows
  // and how many refits it took; empty for other fits.
  std::string energy_bound;
  std::vector<ParameterReport> parameters;
  // Empty when the covariance exists; otherwise names the parameters the
  // data cannot determine, e.g. "not identifiable: eta, kd".
  std::string identifiability;
  // The other parameters' standard deviations hold those at their values
  // (fitting/covariance_internal.h); false when there are none.
  bool stddev_conditional = false;
};

// Records the weighting in effect in the report, after the solve: an
// unknown level is estimated from the final cost.
void ReportWeighting(const Weighting& weighting, FitReport* report);

// A fit's parameters and its report (ThreadFitResult = FitResult<ThreadParams>,
// ...).
template <typename P>
struct FitResult {
  P params;
  FitReport report;
};

// Throws InputError naming the table's source when no row has a weight
// above 0 (nothing to fit).
void RequireWeightedRows(const MeasurementTable& table);
// The same for rows counted as read (`table`: their source).
void RequireWeightedRows(const MeasurementTable& table, bool any_weighted);

// For a reflection-only model (`model`: "cloth", "lafortune"): the number
// of rows of `table` with the light or the view below the surface, which
// its fit leaves out and counts in FitReport::rows_not_used. Throws
// InputError naming the table's source when no row is left.
int CountNotReflection(const MeasurementTable& table, const std::string& model);
// The same for rows counted as read: `not_reflection` of `rows`.
int CountNotReflection(const MeasurementTable& table, size_t not_reflection,
                       size_t rows, const std::string& model);

// One-channel tables fit one value of an rgb parameter: every reported
// parameter named PREFIX`name`_g or PREFIX`name`_b takes the value of
// PREFIX`name`_r (e.g. "threads[1].albedo_g" that of "threads[1].albedo_r").
void ReportChannelsFollowRed(const std::string& name, FitReport* report);

// One-channel tables fit one value of an rgb parameter: returns
// (rgb.x, rgb.x, rgb.x) and reports that value for `name`_g and `name`_b.
glm::dvec3 OneChannelRgb(const std::string& name, const glm::dvec3& rgb,
                         FitReport* report);

// The "fit" object of a result file, as JSON text (no wall time).
std::string FitReportJson(const FitReport& report);
// A one-screen summary; `truth` (same order as parameters, may be empty)
// adds a column of true values.
std::string FitReportText(const FitReport& report,
                          const std::vector<double>& truth = {});

}  // namespace clothfit
