#include "fitting/lafortune_samples.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <unordered_map>

#include "fitting/residual_weight.h"
#include "io/input_error.h"
#include "models/evaluate.h"

namespace clothfit {
namespace {

long long Round(double x) { return std::llround(x * 1e9); }

struct KeyHash {
  size_t operator()(const std::array<long long, 6>& k) const {
    size_t h = 1469598103934665603ULL;
    for (long long v : k) h = (h ^ static_cast<size_t>(v)) * 1099511628211ULL;
    return h;
  }
};

}  // namespace

ViewIndex::ViewIndex(const MeasurementTable& table) {
  std::unordered_map<std::array<long long, 6>, int, KeyHash> views, pairs,
      lights;
  row_view_.resize(table.rows.size());
  row_pair_.resize(table.rows.size());
  row_light_.resize(table.rows.size());
  for (size_t i = 0; i < table.rows.size(); ++i) {
    const TableRow& row = table.rows[i];
    const std::array<long long, 6> view = {
        Round(row.wo.x), Round(row.wo.y), Round(row.wo.z), 0, 0, 0};
    std::array<long long, 6> pair = view;
    pair[3] = Round(row.wi.x);
    pair[4] = Round(row.wi.y);
    pair[5] = Round(row.wi.z);
    auto v = views.emplace(view, static_cast<int>(views_.size()));
    if (v.second) views_.push_back(row.wo);
    row_view_[i] = v.first->second;
    row_pair_[i] = pairs.emplace(pair, pairs_).first->second;
    if (row_pair_[i] == pairs_) ++pairs_;
    const std::array<long long, 6> light = {pair[3], pair[4], pair[5], 0, 0, 0};
    row_light_[i] = lights.emplace(light, lights_).first->second;
    if (row_light_[i] == lights_) ++lights_;
  }
}

TexelSamples CollectSamples(const MeasurementTable& table,
                            const Weighting& weighting, const ViewIndex& views,
                            const std::vector<size_t>& rows, int* skipped) {
  if (table.quantity == Quantity::kTransmittance) {
    throw InputError(
        "a Lafortune model predicts reflection (brdf or "
        "cosine_weighted), not transmittance");
  }
  TexelSamples s;
  s.views = views.views();
  std::vector<double> alpha_sum(s.views.size(), 0.0);
  std::vector<int> alpha_count(s.views.size(), 0);
  std::vector<int> slot(views.pairs(), -1);  // pair -> sample
  std::vector<glm::dvec3> sum_wy;            // per sample: sum w y
  int dropped = 0;
  for (size_t index : rows) {
    const TableRow& row = table.rows[index];
    if (!IsReflectionRow(row)) {
      ++dropped;
      continue;
    }
    // Values as rho; sigma likewise (rho = f wi.z).
    const double to_rho = CosineWeightedFactor(table.quantity, row.wi.z);
    const glm::dvec3 w = weighting.InverseVariance(row, to_rho);
    const int view = views.RowView(index);
    int& k = slot[views.RowPair(index)];
    if (k < 0) {
      k = static_cast<int>(s.l.size());
      s.l.push_back(row.wi);
      s.v.push_back(row.wo);
      s.view.push_back(view);
      s.weight.push_back(glm::dvec3(0.0));
      s.value.push_back(glm::dvec3(0.0));
      s.source_line.push_back(row.source_line);
      sum_wy.push_back(glm::dvec3(0.0));
    }
    s.weight[k] += w;
    sum_wy[k] += w * row.value * to_rho;
    s.value[k] += row.value * to_rho;  // plain sum, for zero weights
    const glm::dvec3 rho = row.value * to_rho;
    s.largest_row_value = std::max({s.largest_row_value, rho.x, rho.y, rho.z});
    s.count_rows.resize(s.l.size(), 0);
    ++s.count_rows[k];
    alpha_sum[view] += row.alpha;
    ++alpha_count[view];
  }
  for (size_t k = 0; k < s.l.size(); ++k) {
    for (int c = 0; c < 3; ++c) {
      s.value[k][c] = s.weight[k][c] > 0.0 ? sum_wy[k][c] / s.weight[k][c]
                                           : s.value[k][c] / s.count_rows[k];
    }
  }
  if (table.has_normal) {
    glm::dvec3 normal_sum(0.0);
    for (size_t index : rows) normal_sum += table.rows[index].normal;
    if (glm::length(normal_sum) > 0.0) s.normal = glm::normalize(normal_sum);
    const TexelFrame frame = MakeTexelFrame(s.normal);
    for (size_t k = 0; k < s.l.size(); ++k) {
      s.l[k] = ToTexelFrame(frame, s.l[k]);
      s.v[k] = ToTexelFrame(frame, s.v[k]);
    }
  }
  s.view_alpha.resize(s.views.size());
  for (size_t k = 0; k < s.views.size(); ++k) {
    s.view_alpha[k] = alpha_count[k] ? alpha_sum[k] / alpha_count[k] : 1.0;
  }
  if (skipped) *skipped = dropped;
  return s;
}

void LafortuneErrors(const LafortuneModel& model, const MeasurementTable& table,
                     const ViewIndex& views, const std::vector<size_t>& rows,
                     double* rms, double* relative_rms,
                     double* view_relative_rms) {
  const bool same_views = model.lut.views.size() == views.views().size();
  const TexelFrame frame = MakeTexelFrame(model.normal);
  double se = 0.0, ss = 0.0;
  size_t n = 0;
  // Per view: sums of model - data and of data, and the row count.
  const size_t n_views = views.views().size();
  std::vector<glm::dvec3> view_d(n_views, glm::dvec3(0.0)),
      view_y(n_views, glm::dvec3(0.0));
  std::vector<int> view_n(n_views, 0);
  for (size_t index : rows) {
    const TableRow& row = table.rows[index];
    if (!IsReflectionRow(row)) continue;
    // In the table's quantity, as every other fit reports (the model is
    // rho, f = rho / wi.z).
    const glm::dvec3& y = row.value;
    const glm::dvec3 t = same_views ? model.lut.color[views.RowView(index)]
                                    : LookupView(model.lut, row.wo).color;
    const glm::dvec3 d =
        t *
            LafortuneF1(model.params, ToTexelFrame(frame, row.wi),
                        ToTexelFrame(frame, row.wo)) *
            QuantityFactor(Quantity::kCosineWeighted, table.quantity,
                           row.wi.z) -
        y;
    se += glm::dot(d, d);
    ss += glm::dot(y, y);
    ++n;
    const int view = views.RowView(index);
    view_d[view] += d;
    view_y[view] += y;
    ++view_n[view];
  }
  *rms = n ? std::sqrt(se / (3.0 * n)) : 0.0;
  *relative_rms = ss > 0.0 ? std::sqrt(se / ss) : 0.0;
  if (view_relative_rms) {
    double vse = 0.0, vss = 0.0;
    for (size_t k = 0; k < n_views; ++k) {
      if (view_n[k] == 0) continue;
      const glm::dvec3 d = view_d[k] / double(view_n[k]);
      const glm::dvec3 y = view_y[k] / double(view_n[k]);
      vse += glm::dot(d, d);
      vss += glm::dot(y, y);
    }
    *view_relative_rms = vss > 0.0 ? std::sqrt(vse / vss) : 0.0;
  }
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
