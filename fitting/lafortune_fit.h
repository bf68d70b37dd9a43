// Fits Lafortune lobes with a per-view lookup table (Daubert et al. 2001,
// Section 5; docs/models.md) to the samples of one texel (or one whole table):
// a first pass of the lobes by Levenberg-Marquardt with T = 1 (or a warm
// start's T), then by default the lobes and T jointly
// (LafortuneSolve::kJoint), or as the paper alternately the lobes with T
// fixed and every T(v) in closed form per channel (eq. 4:
// T = <f, r> / <f, f> over the samples of view v), until the mean relative
// change of T falls below a threshold or an iteration cap. The joint
// solve's table is normalised to a mean of 1 over its own views (the
// lobes take the scale).
#pragma once

#include <string>
#include <vector>

#include "fitting/fit_result.h"
#include "fitting/lafortune_samples.h"
#include "fitting/linear_solver.h"
#include "io/table.h"
#include "models/lafortune.h"

namespace clothfit {

// How the lobes and the lookup table are solved for: jointly (the lookup
// table eliminated in each step, fitting/lafortune_joint_internal.h), or
// alternately as the paper does (Daubert et al. 2001, Section 5: the lobes
// with T fixed, then T in closed form, until T changes less than
// lut_threshold).
enum class LafortuneSolve { kJoint, kAlternate };

struct LafortuneFitOptions {
  // The joint solve by default: it reaches the optimum of representable
  // data (relative RMS 2e-11 where the alternation stops at 0.019). Where
  // a view's samples are out of the lobes' reach its projected T grows,
  // and the table's interpolation carries that T to directions the lobes
  // do reach; a texel whose joint optimum so reflects more than it
  // receives (it would be scaled, fitting/energy.h) is fitted again by the
  // alternation, which keeps T near its start, and the less scaled of the
  // two is kept (FitReport::solve_fallback; 17 of 1,024 level-0 texels of
  // the paper's 32 x 32 virtual-gonio map, docs/lafortune.md).
  LafortuneSolve solve = LafortuneSolve::kJoint;
  // The joint solve stops when an iteration lowers the cost by less than
  // this fraction (or after max_iterations). Measured on an 8 x 8 gonio
  // mip map (85 fits, one thread, two runs each): 1e-5 5.2-6.1 s, mean
  // level-0 error 0.4606; 3e-5 4.4-5.1 s, 0.4608; 1e-4 4.1-4.6 s, 0.4629.
  // Exactly representable data reach 2e-11 with each (the cost falls by
  // orders of magnitude per step there).
  double joint_function_tolerance = 3e-5;
  int lobes = 2;               // K, 0 to 3
  bool lookup_table = true;    // false: T = 1 (no alternation)
  double lut_threshold = 0.1;  // mean relative change of T that stops
  int max_alternations = 10;   // cap on lobe/T alternations
  // A view gets its own lookup-table entry only with at least this many
  // samples (distinct lights); the others take T interpolated from those
  // entries (LookupView; 1 when no view has enough). A free T fits a view's
  // few samples exactly and learns nothing for the rest: on CUReT tables
  // (205 rows, 147 views, 112 with one row) the table gained nothing on
  // held-out rows; in bench --quick (12 training lights per view) a table
  // at 8 samples lost 8.5 % on held-out lights (0.482 against 0.444
  // without), while with 48 lights per view (the full bench) it gains
  // 14 % (0.502 against 0.581).
  int min_lut_samples = 16;
  int max_iterations = 50;  // Levenberg-Marquardt iterations per pass
  // Ceres' function_tolerance: a solve stops when an iteration lowers the
  // cost by less than this fraction. Measured on gonio texels (8 x 8 plain
  // weave, 64 x 64 directions, K = 2; docs/lafortune.md): 1e-6 (Ceres'
  // default) 106 iterations per fit, 1e-5 76 for +0.9 % error, 1e-4 53 for
  // +2.8 %.
  double function_tolerance = 1e-5;
  // Of the Levenberg-Marquardt steps (fitting/linear_solver.h): a texel
  // channel has at most 13 parameters and thousands of samples, where the
  // normal equations are cheaper than QR of the Jacobian (docs/bench.md).
  LinearSolver linear_solver = LinearSolver::kDenseNormalCholesky;
  // First pass: channels 1 and 2 start from channel 0's solution, scaled
  // (measured: 20 % fewer iterations, 0.7 % lower error).
  bool warm_channels = true;
  // The first pass (the paper's start: most of the iterations) fits every
  // n-th sample of a texel with more than 1,024; later passes use all.
  // Measured (8 x 8 gonio texels, 4,096 samples each, K = 2): n = 4 is 34 %
  // faster with 1 % lower mean error (the later passes refine); n = 16
  // loses 2 %. 1 = off.
  int first_pass_subsample = 4;
  // Above this many samples a lobe solve hands the solver compressed
  // chunks of samples whose terms it computes as it evaluates them
  // (fitting/lafortune_lobes.cc), not one block over a copy of every
  // sample's terms: the copy and the solver's dense Jacobian of every
  // sample were 1.9 GB of a 10^7-row fit. The same steps either way (the
  // chunks' QR factors have the rows' normal equations).
  size_t max_one_block_samples = size_t{1} << 16;
  // Starts: the paper's (grey, moderate highlight, slightly anisotropic
  // lobes); with data_driven_start also one scaled to the data (diffuse
  // from a closed-form least squares, lobes sized to the brightest excess),
  // keeping the better after the first pass. Measured on virtual-gonio
  // texels (4 x 4 plain weave, 64 x 64 directions, K = 2): 1 % lower mean
  // relative error for 1.56 x the time, so it is off by default.
  bool data_driven_start = false;
  // If set (a texel's children at the mip level below), the start is the
  // candidate with the lowest cost on the samples (with its lookup table)
  // instead of the paper's; candidates with another lobe count are
  // ignored.
  std::vector<const LafortuneModel*> warm_starts;
  // If set (`fit --init`), the start when no warm start applies, in place
  // of the paper's, when it has `lobes` lobes; its lookup table is used
  // too when its views are the samples' views (each within 1e-9).
  const LafortuneModel* start = nullptr;
};

// The views of `samples` that get a lookup-table entry of their own: those
// with at least max(1, min_lut_samples) samples (LafortuneFitOptions).
std::vector<bool> LafortuneOwnedViews(const TexelSamples& samples,
                                      int min_lut_samples);

// The fitted model (lobes, lookup table, normal) and its report: usable,
// converged (the alternation stopped because T changed less than
// lut_threshold, or there is no lookup table; not at the
// max_alternations cap; no lobe entry at a search limit, whose count is
// at_search_limit and the first of which the message names), termination (in
// words), iterations (all passes), alternations, lut_change (last pass),
// final_cost (1/2 sum of weighted squared residuals as rho, as Ceres'), rms and
// relative_rms (of the samples as rho), residuals and rows. Standard
// deviations are a table fit's (FitLafortuneTable,
// fitting/lafortune_covariance.h), not every texel's.
using LafortuneFitResult = FitResult<LafortuneModel>;

// The lobe entries of `p` that lie on a bound that only limits the search
// (N = 0.5 or 200; models/lafortune.h), as report names
// ("lobes[1].N_r") with their values: a lobe the solver pushed to the edge
// of its range - a collapsed lobe (N = 0.5, a constant in disguise) or one
// narrower than the data resolve (N = 200) - which is not a converged fit.
// |C| at its reach (the energy normalisation) is a physical bound.
struct LafortuneLimit {
  std::string name;
  double value;
};
std::vector<LafortuneLimit> LafortuneAtSearchLimit(const LafortuneParams& p);

// Makes the report of a solution p not converged, with a message, when a
// lobe entry is on a search limit (their count in at_search_limit) or the
// model was scaled to conserve energy (report->energy_scale < 1).
void ReportLafortuneLimits(const LafortuneParams& p, FitReport* report);

// "the model value is (...) at line L of the table, light (...) and view
// (...) in the texel's frame" for the first sample whose model value with
// lookup table t is not finite; "non-finite model values" if none.
std::string LafortuneNonFiniteSample(const TexelSamples& s,
                                     const std::vector<glm::dvec3>& t,
                                     const LafortuneParams& p);

// With the joint solve, a texel whose joint optimum had to be scaled to
// conserve energy is fitted again by the alternation and the less scaled
// result kept (report.solve_fallback, the termination says why).
// Never throws for data problems: an empty texel, all-zero values or views
// without signal give a usable zero/diffuse model or usable = false with a
// message; nothing is NaN.
LafortuneFitResult FitLafortune(const TexelSamples& samples,
                                const LafortuneFitOptions& options);

}  // namespace clothfit
