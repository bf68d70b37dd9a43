// Fits Lafortune lobes with a per-view lookup table (Daubert et al. 2001,
// Section 5; SPEC §3.3) to the samples of one texel (or one whole table):
// alternately the lobes by Levenberg-Marquardt with T fixed (first pass
// T = 1), then every T(v) in closed form per channel (eq. 4:
// T = <f, r> / <f, f> over the samples of view v), until the mean relative
// change of T falls below a threshold or an iteration cap.
#pragma once

#include <string>
#include <vector>

#include "fitting/fit_result.h"
#include "fitting/linear_solver.h"
#include "io/table.h"
#include "models/lafortune.h"

namespace clothfit {

// The samples of one texel: directions in its local frame, values
// (cosine-weighted), 1/sigma^2 * weight, and the index of the view.
struct TexelSamples {
  // The texel's average normal (surface frame); l and v are in the frame
  // MakeTexelFrame(normal).
  glm::dvec3 normal{0.0, 0.0, 1.0};
  std::vector<glm::dvec3> l, v, value, weight;
  std::vector<int> view;           // index into views
  std::vector<int> count_rows;     // table rows merged into each sample
  std::vector<int> source_line;    // table line of each sample's first row
  std::vector<glm::dvec3> views;   // the distinct view directions
  std::vector<double> view_alpha;  // mean alpha of each view's samples
  size_t size() const { return l.size(); }
};

// The distinct view directions (wo) and (light, view) pairs of a table,
// equal to 1e-9, in order of first appearance, and each row's view and
// pair. Built once per table; the views are shared by all texels so that
// their lookup tables line up.
class ViewIndex {
 public:
  explicit ViewIndex(const MeasurementTable& table);
  const std::vector<glm::dvec3>& views() const { return views_; }
  int RowView(size_t row) const { return row_view_[row]; }
  int RowPair(size_t row) const { return row_pair_[row]; }
  int pairs() const { return pairs_; }

 private:
  std::vector<glm::dvec3> views_;
  std::vector<int> row_view_, row_pair_;
  int pairs_ = 0;
};

// The samples of the given rows of a table, as the cosine-weighted
// quantity, with all of the index's views (a view without samples gets
// alpha 1 and keeps T = 1). Rows with the same (light, view) pair are
// merged into one sample: their weighted mean value, with the sum of their
// weights, which leaves the least-squares minimiser unchanged (sum_i w_i
// (m - y_i)^2 = W (m - y_mean)^2 + const) and keeps the work of a pooled
// mip-level fit at that of one texel. Rows that are not reflection (wi.z
// <= 0 or wo.z <= 0) are skipped and counted in *skipped (may be null).
// A table with normal columns gives the rows' mean normal as the texel's
// (a pooled group: the average of its texels' normals, as the paper's
// Section 5.1), and l, v are rotated into its frame; else the surface
// frame.
// Throws InputError for a transmittance table.
TexelSamples CollectSamples(const MeasurementTable& table,
                            const ViewIndex& views,
                            const std::vector<size_t>& rows, int* skipped);

// RMS and relative RMS error of a model over table rows (as rho). Rows
// at a stored view use its lookup-table entry directly (no interpolation).
// view_relative_rms (may be null): the relative RMS error of each view's
// colour - the mean over the view's rows (all its lights) of model and data
// - over the views: the view-dependent colour the paper's Fig. 5 shows
// (colour shifts at grazing views), which the lookup table is for.
void LafortuneErrors(const LafortuneModel& model, const MeasurementTable& table,
                     const ViewIndex& views, const std::vector<size_t>& rows,
                     double* rms, double* relative_rms,
                     double* view_relative_rms = nullptr);

struct LafortuneFitOptions {
  int lobes = 2;               // K, 0 to 3
  bool lookup_table = true;    // false: T = 1 (no alternation)
  double lut_threshold = 0.1;  // mean relative change of T that stops
  int max_alternations = 10;   // cap on lobe/T alternations
  int max_iterations = 50;     // Levenberg-Marquardt iterations per pass
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

struct LafortuneFitResult {
  LafortuneModel model;
  bool usable = false;
  std::string message;
  int alternations = 0;
  int iterations = 0;         // Levenberg-Marquardt iterations, all passes
  double rms = 0.0;           // of model - value (cosine-weighted)
  double relative_rms = 0.0;  // rms / rms(value)
  double lut_change = 0.0;    // mean relative change of T, last pass
  // 1/2 sum of weighted squared residuals (cosine-weighted), as Ceres'.
  double final_cost = 0.0;
  // The alternation stopped because T changed less than lut_threshold (or
  // there is no lookup table), not at the max_alternations cap.
  bool converged = false;
  std::string termination;  // why it stopped, in words
};

// Never throws for data problems: an empty texel, all-zero values or views
// without signal give a usable zero/diffuse model or usable = false with a
// message; nothing is NaN.
LafortuneFitResult FitLafortune(const TexelSamples& samples,
                                const LafortuneFitOptions& options);

}  // namespace clothfit
