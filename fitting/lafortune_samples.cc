#include "fitting/lafortune_samples.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "fitting/residual_weight.h"
#include "io/input_error.h"
#include "models/evaluate.h"

namespace clothfit {
namespace {

// The id of each of n items in order of first appearance of its key
// (key_of(i)), and the number of distinct keys.
template <typename KeyOf>
int FirstAppearance(size_t n, const KeyOf& key_of, std::vector<int>* ids) {
  std::vector<int32_t> first;  // the first item of each id
  const auto key_of_id = [&](int32_t id) {
    return key_of(static_cast<size_t>(first[id]));
  };
  FirstAppearanceIds index;
  index.Reserve(n);
  ids->resize(n);
  for (size_t i = 0; i < n; ++i) {
    bool added = false;
    (*ids)[i] = index.Id(key_of(i), key_of_id, &added);
    if (added) first.push_back(static_cast<int32_t>(i));
  }
  return index.size();
}

}  // namespace

ViewIndex::ViewIndex(const MeasurementTable& table) {
  const std::vector<TableRow>& rows = table.rows;
  if (rows.size() > static_cast<size_t>(INT32_MAX)) {
    throw InputError(table.source + ": more than 2^31 rows");
  }
  const int views = FirstAppearance(
      rows.size(), [&](size_t i) { return DirectionKeyOf(rows[i].wo); },
      &row_view_);
  views_.resize(static_cast<size_t>(views));
  for (size_t i = rows.size(); i-- > 0;) views_[row_view_[i]] = rows[i].wo;
  pairs_ = FirstAppearance(
      rows.size(), [&](size_t i) { return PairKeyOf(rows[i].wo, rows[i].wi); },
      &row_pair_);
  lights_ = FirstAppearance(
      rows.size(), [&](size_t i) { return DirectionKeyOf(rows[i].wi); },
      &row_light_);
}

SampleCollector::SampleCollector(const MeasurementTable& table,
                                 const ViewIndex& views, bool one_view)
    : quantity_(table.quantity),
      has_normal_(table.has_normal),
      one_view_(one_view),
      alpha_sum_(one_view ? 1 : views.views().size(), 0.0),
      alpha_count_(one_view ? 1 : views.views().size(), 0),
      slot_(views.pairs(), -1) {
  if (table.quantity == Quantity::kTransmittance) {
    throw InputError(
        "a Lafortune model predicts reflection (brdf or "
        "cosine_weighted), not transmittance");
  }
  if (one_view) {
    s_.views = {glm::dvec3(0.0, 0.0, 1.0)};
  } else {
    s_.views = views.views();
  }
}

SampleCollector::SampleCollector(const MeasurementTable& table, bool one_view)
    : SampleCollector(table, ViewIndex(), one_view) {
  if (!one_view) view_ids_ = std::make_unique<ViewIds>();
  pair_ids_ = std::make_unique<FirstAppearanceIds>();
}

void SampleCollector::Reserve(size_t samples) {
  s_.l.reserve(samples);
  s_.v.reserve(samples);
  s_.view.reserve(samples);
  s_.weight.reserve(samples);
  s_.value.reserve(samples);
  s_.source_line.reserve(samples);
  s_.count_rows.reserve(samples);
  if (pair_ids_) pair_ids_->Reserve(samples);
  sum_wy_.reserve(samples);
}

void SampleCollector::Add(const TableRow& row, const Weighting& weighting) {
  int view = 0;
  if (view_ids_) {  // every row's view, as ViewIndex
    view = view_ids_->Id(row.wo);
    if (alpha_sum_.size() < view_ids_->views().size()) {
      alpha_sum_.push_back(0.0);
      alpha_count_.push_back(0);
    }
  }
  Add(row, view, -1, weighting);
}

int SampleCollector::SampleOf(const TableRow& row, int view, int pair) {
  int k = -1;
  bool added = false;
  if (pair >= 0) {
    k = slot_[pair];
    added = k < 0;
    if (added) k = slot_[pair] = static_cast<int>(s_.l.size());
  } else {
    k = pair_ids_->Id(
        PairKeyOf(row.wo, row.wi),
        [this](int32_t id) { return PairKeyOf(s_.v[id], s_.l[id]); }, &added);
  }
  if (added) {
    s_.l.push_back(row.wi);
    s_.v.push_back(row.wo);
    s_.view.push_back(view);
    s_.weight.push_back(glm::dvec3(0.0));
    s_.value.push_back(glm::dvec3(0.0));
    s_.source_line.push_back(row.source_line);
    s_.count_rows.push_back(0);
    sum_wy_.push_back(glm::dvec3(0.0));
  }
  return k;
}

void SampleCollector::Add(const TableRow& row, int view, int pair,
                          const Weighting& weighting) {
  if (one_view_) view = 0;
  // A pooled group's normal: the average of its rows' (Section 5.1).
  normal_sum_ += row.normal;
  if (!IsReflectionRow(row)) {
    ++dropped_;
    return;
  }
  // Values as rho; sigma likewise (rho = f wi.z).
  const double to_rho = CosineWeightedFactor(quantity_, row.wi.z);
  const glm::dvec3 w = weighting.InverseVariance(row, to_rho);
  const int k = SampleOf(row, view, pair);
  s_.weight[k] += w;
  sum_wy_[k] += w * row.value * to_rho;
  s_.value[k] += row.value * to_rho;  // plain sum, for zero weights
  const glm::dvec3 rho = row.value * to_rho;
  s_.largest_row_value = std::max({s_.largest_row_value, rho.x, rho.y, rho.z});
  ++s_.count_rows[k];
  alpha_sum_[view] += row.alpha;
  ++alpha_count_[view];
}

TexelSamples SampleCollector::Finish(int* skipped) {
  TexelSamples s = std::move(s_);
  if (view_ids_) s.views = view_ids_->TakeViews();
  for (size_t k = 0; k < s.l.size(); ++k) {
    for (int c = 0; c < 3; ++c) {
      s.value[k][c] = s.weight[k][c] > 0.0 ? sum_wy_[k][c] / s.weight[k][c]
                                           : s.value[k][c] / s.count_rows[k];
    }
  }
  if (has_normal_) {
    if (glm::length(normal_sum_) > 0.0) s.normal = glm::normalize(normal_sum_);
    const TexelFrame frame = MakeTexelFrame(s.normal);
    for (size_t k = 0; k < s.l.size(); ++k) {
      s.l[k] = ToTexelFrame(frame, s.l[k]);
      s.v[k] = ToTexelFrame(frame, s.v[k]);
    }
  }
  s.view_alpha.resize(s.views.size());
  for (size_t k = 0; k < s.views.size(); ++k) {
    s.view_alpha[k] = alpha_count_[k] ? alpha_sum_[k] / alpha_count_[k] : 1.0;
  }
  if (skipped) *skipped = dropped_;
  return s;
}

TexelSamples CollectSamples(const MeasurementTable& table,
                            const Weighting& weighting, const ViewIndex& views,
                            const std::vector<size_t>& rows, int* skipped,
                            bool one_view) {
  SampleCollector collector(table, views, one_view);
  collector.Reserve(std::min(rows.size(), static_cast<size_t>(views.pairs())));
  for (size_t index : rows) {
    collector.Add(table.rows[index], views.RowView(index), views.RowPair(index),
                  weighting);
  }
  return collector.Finish(skipped);
}

LafortuneErrorSums::LafortuneErrorSums(const LafortuneModel& model,
                                       const MeasurementTable& table,
                                       const ViewIndex& views)
    : LafortuneErrorSums(
          model, table, model.lut.views.size() == views.views().size(), true) {}

LafortuneErrorSums::LafortuneErrorSums(const LafortuneModel& model,
                                       const MeasurementTable& table,
                                       bool same_views, bool view_sums)
    : model_(model),
      quantity_(table.quantity),
      same_views_(same_views),
      view_sums_(view_sums),
      frame_(MakeTexelFrame(model.normal)) {}

void LafortuneErrorSums::Add(const TableRow& row, int view) {
  if (!IsReflectionRow(row)) return;
  // In the table's quantity, as every other fit reports (the model is
  // rho, f = rho / wi.z).
  const glm::dvec3& y = row.value;
  // T(v): the view's entry, interpolated where the table is not the rows'
  // (or has no entry for the view: a file that changed between passes),
  // 1 without a table.
  const bool own_entry =
      same_views_ && static_cast<size_t>(view) < model_.lut.color.size();
  const glm::dvec3 t =
      own_entry ? model_.lut.color[view] : LookupView(model_.lut, row.wo).color;
  const glm::dvec3 d =
      t *
          LafortuneF1(model_.params, ToTexelFrame(frame_, row.wi),
                      ToTexelFrame(frame_, row.wo)) *
          QuantityFactor(Quantity::kCosineWeighted, quantity_, row.wi.z) -
      y;
  se_ += glm::dot(d, d);
  ss_ += glm::dot(y, y);
  ++n_;
  if (!view_sums_) return;
  if (static_cast<size_t>(view) >= view_n_.size()) {
    view_d_.resize(view + 1, glm::dvec3(0.0));
    view_y_.resize(view + 1, glm::dvec3(0.0));
    view_n_.resize(view + 1, 0);
  }
  view_d_[view] += d;
  view_y_[view] += y;
  ++view_n_[view];
}

void LafortuneErrorSums::Finish(double* rms, double* relative_rms,
                                double* view_relative_rms) const {
  *rms = n_ ? std::sqrt(se_ / (3.0 * n_)) : 0.0;
  *relative_rms = ss_ > 0.0 ? std::sqrt(se_ / ss_) : 0.0;
  if (view_relative_rms && view_sums_) {
    double vse = 0.0, vss = 0.0;
    for (size_t k = 0; k < view_n_.size(); ++k) {
      if (view_n_[k] == 0) continue;
      const glm::dvec3 d = view_d_[k] / double(view_n_[k]);
      const glm::dvec3 y = view_y_[k] / double(view_n_[k]);
      vse += glm::dot(d, d);
      vss += glm::dot(y, y);
    }
    *view_relative_rms = vss > 0.0 ? std::sqrt(vse / vss) : 0.0;
  }
}

void LafortuneErrors(const LafortuneModel& model, const MeasurementTable& table,
                     const ViewIndex& views, const std::vector<size_t>& rows,
                     double* rms, double* relative_rms,
                     double* view_relative_rms) {
  LafortuneErrorSums sums(model, table, views);
  for (size_t index : rows) sums.Add(table.rows[index], views.RowView(index));
  sums.Finish(rms, relative_rms, view_relative_rms);
}

TexelSamples Subsample(const TexelSamples& samples, int stride) {
  TexelSamples sub;
  if (stride <= 1 || samples.size() <= kMinSubsampled) return sub;
  sub.normal = samples.normal;
  sub.views = samples.views;
  sub.view_alpha = samples.view_alpha;
  sub.largest_row_value = samples.largest_row_value;
  for (size_t i = 0; i < samples.size(); ++i) {
    const uint64_t hash = (static_cast<uint64_t>(i) * 2654435761u) >> 7;
    if (hash % static_cast<uint64_t>(stride) != 0) continue;
    sub.l.push_back(samples.l[i]);
    sub.v.push_back(samples.v[i]);
    sub.value.push_back(samples.value[i]);
    sub.weight.push_back(samples.weight[i]);
    sub.view.push_back(samples.view[i]);
    sub.count_rows.push_back(samples.count_rows[i]);
    sub.source_line.push_back(samples.source_line[i]);
  }
  return sub;
}

}  // namespace clothfit
