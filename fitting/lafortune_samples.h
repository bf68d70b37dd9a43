// The samples a Lafortune fit works on (Daubert et al. 2001, Section 5):
// one texel's (or one table's) rows as cosine-weighted values in the
// texel's frame, merged per (light, view) pair, with the measured views
// that index the lookup table; and the errors of a fitted model over
// table rows.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "fitting/direction_ids.h"
#include "fitting/residual_weight.h"
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
  // The largest value of any merged row (rho, any channel), which merging
  // into means would lower; 0 where the samples are the rows themselves.
  double largest_row_value = 0.0;
  size_t size() const { return l.size(); }
};

// The distinct view directions (wo), light directions (wi) and (light,
// view) pairs of a table, equal to 1e-9, in order of first appearance, and
// each row's view, light and pair. Built once per table; the views are shared
// by all texels so that their lookup tables line up.
class ViewIndex {
 public:
  ViewIndex() = default;  // of no rows
  explicit ViewIndex(const MeasurementTable& table);
  const std::vector<glm::dvec3>& views() const { return views_; }
  int RowView(size_t row) const { return row_view_[row]; }
  int RowPair(size_t row) const { return row_pair_[row]; }
  int pairs() const { return pairs_; }
  // The distinct light directions (wi), likewise.
  int RowLight(size_t row) const { return row_light_[row]; }
  int lights() const { return lights_; }

 private:
  std::vector<glm::dvec3> views_;
  std::vector<int> row_view_, row_pair_, row_light_;
  int pairs_ = 0, lights_ = 0;
};

// The samples of the given rows of a table, as the cosine-weighted
// quantity, weighted by `weighting`, with all of the index's views (a view
// without samples gets alpha 1 and keeps T = 1). Rows with the same (light,
// view) pair are merged into one sample: their weighted mean value, with the
// sum of their weights, which leaves the least-squares minimiser unchanged
// (sum_i w_i (m - y_i)^2 = W (m - y_mean)^2 + const) and keeps the work of a
// pooled mip-level fit at that of one texel. Rows that are not reflection (wi.z
// <= 0 or wo.z <= 0) are skipped and counted in *skipped (may be null).
// A table with normal columns gives the rows' mean normal as the texel's
// (a pooled group: the average of its texels' normals, as the paper's
// Section 5.1), and l, v are rotated into its frame; else the surface
// frame.
// one_view: as SampleCollector's. Throws InputError for a transmittance
// table.
TexelSamples CollectSamples(const MeasurementTable& table,
                            const Weighting& weighting, const ViewIndex& views,
                            const std::vector<size_t>& rows, int* skipped,
                            bool one_view = false);

// CollectSamples one row at a time, for rows that are not held in one
// table (a texture streamed from its images, fitting/lafortune_merge.h):
// Add the rows in the order CollectSamples would see them, each with its
// view and pair of the index, then Finish. The same sums in the same
// order: the same samples, bit for bit.
class SampleCollector {
 public:
  // `table`: the quantity and has_normal of the rows (no rows needed).
  // one_view: the samples' views are one, (0, 0, 1), that every row's
  // view is taken as (for a fit without a lookup table, which needs no
  // per-view arrays: a table of random directions has one view a row).
  SampleCollector(const MeasurementTable& table, const ViewIndex& views,
                  bool one_view = false);
  // Without an index: the collector tells the rows' views and pairs apart
  // itself (direction_ids.h), as a ViewIndex of the same rows would, for
  // rows read one at a time (Add without view and pair). Its pairs' keys
  // are the samples' own directions: no copy per row.
  SampleCollector(const MeasurementTable& table, bool one_view);
  // Room for this many samples (at most the rows to be added).
  void Reserve(size_t samples);
  void Add(const TableRow& row, int view, int pair, const Weighting& weighting);
  // The same without an index.
  void Add(const TableRow& row, const Weighting& weighting);
  // The samples; *skipped (may be null) the rows that are not reflection.
  TexelSamples Finish(int* skipped);

 private:
  // The sample of the row's pair (`pair` of the index, or -1: found by its
  // directions), added when new.
  int SampleOf(const TableRow& row, int view, int pair);

  Quantity quantity_;
  bool has_normal_;
  bool one_view_;
  TexelSamples s_;
  std::vector<double> alpha_sum_;
  std::vector<int> alpha_count_;
  std::vector<int> slot_;           // pair -> sample
  std::vector<glm::dvec3> sum_wy_;  // per sample: sum w y
  glm::dvec3 normal_sum_{0.0};
  int dropped_ = 0;
  // Without an index: the views, and the samples' pairs.
  std::unique_ptr<ViewIds> view_ids_;
  std::unique_ptr<FirstAppearanceIds> pair_ids_;
};

// RMS and relative RMS error of a model over table rows, in the table's
// quantity. Rows at a stored view use its lookup-table entry directly (no
// interpolation). view_relative_rms (may be null): the relative RMS error of
// each view's colour - the mean over the view's rows (all its lights) of model
// and data
// - over the views: the view-dependent colour the paper's Fig. 5 shows
// (colour shifts at grazing views), which the lookup table is for.
void LafortuneErrors(const LafortuneModel& model, const MeasurementTable& table,
                     const ViewIndex& views, const std::vector<size_t>& rows,
                     double* rms, double* relative_rms,
                     double* view_relative_rms = nullptr);

// LafortuneErrors one row at a time (as SampleCollector): Add the rows in
// the order LafortuneErrors would see them, then Finish.
class LafortuneErrorSums {
 public:
  // `model` must outlive this; `table`: the rows' quantity.
  LafortuneErrorSums(const LafortuneModel& model, const MeasurementTable& table,
                     const ViewIndex& views);
  // For views numbered as they come (ViewIds): same_views when the
  // model's lookup table has the rows' views in the same order (rows take
  // their view's entry; else it is interpolated); view_sums: whether
  // Finish gives the views' error (else it leaves it unchanged).
  LafortuneErrorSums(const LafortuneModel& model, const MeasurementTable& table,
                     bool same_views, bool view_sums);
  void Add(const TableRow& row, int view);
  void Finish(double* rms, double* relative_rms,
              double* view_relative_rms) const;

 private:
  const LafortuneModel& model_;
  Quantity quantity_;
  bool same_views_;
  bool view_sums_;
  TexelFrame frame_;
  double se_ = 0.0, ss_ = 0.0;
  size_t n_ = 0;
  // Per view: sums of model - data and of data, and the row count.
  std::vector<glm::dvec3> view_d_, view_y_;
  std::vector<int> view_n_;
};

// Every stride-th sample of a scrambled order (Knuth's multiplicative hash
// of the index), so that the subset spreads over all views and lights;
// empty when stride <= 1 or the texel has at most kMinSubsampled samples.
inline constexpr size_t kMinSubsampled = 1024;
TexelSamples Subsample(const TexelSamples& samples, int stride);

}  // namespace clothfit
