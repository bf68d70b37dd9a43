// Spatially varying Lafortune fits and mip-level group fits (Daubert et
// al. 2001, Section 5.1): every texel of a table with s,t columns is fitted
// on its own; level l+1 pools the samples of each 2 x 2 group of level-l
// texels and fits again, down to 1 x 1, so the work per level stays
// constant. Texels are fitted in parallel on a pool of threads; the results
// do not depend on the number of threads.
#pragma once

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "fitting/lafortune_fit.h"
#include "fitting/lafortune_samples.h"
#include "io/lafortune_mipmap.h"

namespace clothfit {

struct LafortuneMipOptions {
  LafortuneFitOptions fit;
  bool mip = true;  // all levels down to 1 x 1; false: level 0 only
  int threads = 0;  // 0: std::thread::hardware_concurrency()
  // > 0: per texel, the smallest lobe count K in 0..3 whose relative RMS
  // error is at most this (else the K with the lowest error).
  double tolerance = 0.0;
  // The weights of the rows (fitting/residual_weight.h); by default the
  // table's sigma, else every row alike (LafortuneWeighting).
  NoiseModel noise;
  // Told (texels done, texels in all) as fits finish; called from one
  // thread at a time.
  std::function<void(int, int)> progress;
};

struct LafortuneLevel {
  int width = 0, height = 0;
  // y * width + x; report.rows: the texel's table rows, errors over them.
  std::vector<LafortuneFitResult> texels;
  size_t samples = 0;    // all samples of the level
  double seconds = 0.0;  // wall time of the level's fits
};

struct LafortuneMipResult {
  std::vector<glm::dvec3> views;  // the lookup tables' views (all texels)
  std::vector<LafortuneLevel> levels;
  int fits = 0;
  double seconds = 0.0;
};

// The weighting of a Lafortune fit: `noise`, whose default for a table
// without sigma is absolute (every row alike), not relative as for the
// other models. Measured: with relative weights the alternation of lobes
// and lookup table ends worse than without a table (relative RMS 0.30
// against 0.17 on view-dependent colour, tests/lafortune_test.cc), so
// relative weighting is an option here (--noise relative) until the joint
// solve weighs both alike.
Weighting LafortuneWeighting(const MeasurementTable& table,
                             const NoiseModel& noise);
// The same for a table read row by row (Weighting's channel_values).
Weighting LafortuneWeighting(
    const MeasurementTable& table, const NoiseModel& noise,
    const std::function<std::vector<double>(int channel)>& channel_values);

// One texel (or a whole table): the fit of the given rows with
// options.fit, or with options.tolerance > 0 the smallest K in 0..3 whose
// relative RMS over the rows is at most the tolerance (else the best K).
LafortuneFitResult FitTexelRows(const MeasurementTable& table,
                                const Weighting& weighting,
                                const ViewIndex& views,
                                const std::vector<size_t>& rows,
                                const LafortuneMipOptions& options);

// The steps of FitTexelRows, for fits whose rows are not in one table
// (fitting/lafortune_merge.h): the lobe counts it tries, in order; the fit
// of one count on collected samples (`skipped` rows not reflection); and the
// choice among the fits, offered in that order with their errors over the
// rows set: Offer returns true when the choice is made (the tolerance met),
// Take gives the chosen fit.
std::vector<int> LafortuneCandidateLobes(const LafortuneMipOptions& options);
LafortuneFitResult FitLafortuneCandidate(const TexelSamples& samples, int lobes,
                                         int skipped,
                                         const LafortuneMipOptions& options);
class LafortuneCandidates {
 public:
  explicit LafortuneCandidates(double tolerance) : tolerance_(tolerance) {}
  bool Offer(LafortuneFitResult fit);
  LafortuneFitResult Take() { return std::move(best_); }

 private:
  double tolerance_;
  bool offered_ = false;
  LafortuneFitResult best_;
};

// The models of the texels of `below` in each group of the next level
// (width x height texels; MipParent), in row order: the starts of the
// groups' fits.
std::vector<std::vector<const LafortuneModel*>> LafortuneChildren(
    const LafortuneLevel& below, int width, int height);

// Runs job(0) .. job(jobs - 1) on `threads` threads (0: every core), and
// done() after each, one thread at a time; rethrows the first exception
// once all have run.
void RunTexelJobs(size_t jobs, int threads,
                  const std::function<void(size_t)>& job,
                  const std::function<void()>& done = {});

// One model for a whole table (its s,t columns, if any, ignored): the fit
// of every row as FitTexelRows, the rows that are not reflection left out
// and counted in report.rows_not_used (InputError naming the table when
// none is left), and the model's values in report.parameters with their
// standard deviations at the lookup table's gauge
// (fitting/lafortune_covariance.h), or report.identifiability saying why
// there are none.
LafortuneFitResult FitLafortuneTable(const MeasurementTable& table,
                                     const LafortuneMipOptions& options);

// The rows of a table, passed over as many times as a fit needs.
struct TableRowPasses {
  // The columns, metadata and source (its rows, if any, are not read).
  const MeasurementTable* table = nullptr;
  // Calls row(r) for each row, in the same order on every call (a file
  // read again each time).
  std::function<void(const std::function<void(const TableRow&)>& row)> each;
};

// FitLafortuneTable over rows that are not held: the samples are collected
// in one pass (merged per light and view as they come), the errors over
// the rows taken in another once the samples are released, so that a
// table of 10^7 rows needs the samples' memory (about 110 bytes a
// distinct light and view), not the table's besides. One pass more per
// candidate with options.tolerance > 0, and three for the default floor
// of relative noise (each channel's median). FitLafortuneTable is this
// over the table's rows: the same fit, bit for bit.
LafortuneFitResult FitLafortuneRows(const TableRowPasses& rows,
                                    const LafortuneMipOptions& options);

// Throws InputError for a table without s,t columns or a transmittance
// table. Level 0 is (max s + 1) x (max t + 1); a level of odd size pools
// its last row/column into the group before (ROUND_DOWN, as OpenEXR).
LafortuneMipResult FitLafortuneMip(const MeasurementTable& table,
                                   const LafortuneMipOptions& options);

// What a texel map's fits came to, per level and over all: the texels
// that reached no usable solution, have a lobe entry at a search limit
// (LafortuneAtSearchLimit) or stopped at the alternation cap, each with
// where the first one is and why.
struct LafortuneLevelSummary {
  int width = 0, height = 0;
  size_t samples = 0;
  double mean_relative_rms = 0.0, mean_view_relative_rms = 0.0;
  int lobe_counts[4] = {0, 0, 0, 0};  // texels with 0..3 lobes
  double mean_alternations = 0.0, mean_iterations = 0.0;
  int at_search_limit = 0;  // texels with a lobe entry at a search limit
  // Texels scaled down to conserve energy (FitReport::energy_scale), and
  // the largest directional albedo of the level's written texels before
  // that scaling.
  int energy_scaled = 0;
  double max_albedo = 0.0;
  // Texels whose joint solve fell back to the alternation
  // (FitReport::solve_fallback).
  int solve_fallback = 0;
};
struct LafortuneMipSummary {
  std::vector<LafortuneLevelSummary> levels;
  int unusable = 0, not_converged = 0, at_search_limit = 0, energy_scaled = 0;
  // "level L, texel (x, y): why" of the first of each.
  std::string first_unusable, first_not_converged, first_at_search_limit,
      first_energy_scaled;
  double worst_relative_rms = 0.0;
};
LafortuneMipSummary SummarizeLafortuneMip(const LafortuneMipResult& result);

// The index, in `level` of r, of the group that level-0 texel (s, t) joins
// (MipParent per level, as FitLafortuneMip pools them); -1 when (s, t) is
// outside level 0 or the level does not exist.
int LafortuneMipGroup(const LafortuneMipResult& r, size_t level, int s, int t);

// The result as a parameter mip map (io/lafortune_mipmap.h), what the fits
// came to in the index's metadata.fit, and there as "selection" the report
// of a held-out selection when given (SelectionReportJson; "" for none).
ParamMipmap ToParamMipmap(const LafortuneMipResult& result,
                          const std::string& selection_json = "");

}  // namespace clothfit
