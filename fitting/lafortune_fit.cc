#include "fitting/lafortune_fit.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <sstream>
#include <unordered_map>

#include "fitting/ceres_linear_solver_internal.h"
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

// All residuals of one channel of one texel: (T(v_i) f1(l_i, v_i) - y_i)
// sqrt(w_i), with T fixed (eq. 3 with the lookup table of the last pass).
// Per sample the fixed terms are precomputed: the products l_x v_x,
// l_y v_y, l_z v_z, the foreshortening max(l_z, 0), T sqrt(w) and
// y sqrt(w), so that the solver's many evaluations do only the lobes.
struct ChannelTerms {
  double xx, yy, zz, lz, scale, target;
};

template <int kLobes>
struct ChannelResidual {
  const std::vector<ChannelTerms> terms;

  template <typename T>
  bool operator()(const T* x, T* residual) const {
    for (size_t i = 0; i < terms.size(); ++i) {
      const ChannelTerms& s = terms[i];
      T sum = x[0];
      for (int k = 0; k < kLobes; ++k) {
        const T* lobe = x + 1 + 4 * k;
        sum += LobePower(lobe[0] * s.xx + lobe[1] * s.yy + lobe[2] * s.zz,
                         lobe[3]);
      }
      residual[i] = sum * (s.lz * s.scale) - s.target;
    }
    return true;
  }

  static ceres::CostFunction* Create(std::vector<ChannelTerms> terms) {
    const int n = static_cast<int>(terms.size());
    return new ceres::AutoDiffCostFunction<ChannelResidual, ceres::DYNAMIC,
                                           1 + 4 * kLobes>(
        new ChannelResidual{std::move(terms)}, n);
  }
};

std::vector<ChannelTerms> MakeChannelTerms(const TexelSamples& s,
                                           const std::vector<double>& lut,
                                           int channel) {
  std::vector<ChannelTerms> terms(s.size());
  for (size_t i = 0; i < s.size(); ++i) {
    const glm::dvec3& l = s.l[i];
    const glm::dvec3& v = s.v[i];
    const double root_w = std::sqrt(s.weight[i][channel]);
    terms[i] = {l.x * v.x,
                l.y * v.y,
                l.z * v.z,
                std::max(l.z, 0.0),
                lut[s.view[i]] * root_w,
                s.value[i][channel] * root_w};
  }
  return terms;
}

ceres::CostFunction* MakeChannelCost(int lobes,
                                     std::vector<ChannelTerms> terms) {
  switch (lobes) {
    case 0:
      return ChannelResidual<0>::Create(std::move(terms));
    case 1:
      return ChannelResidual<1>::Create(std::move(terms));
    case 2:
      return ChannelResidual<2>::Create(std::move(terms));
    default:
      return ChannelResidual<3>::Create(std::move(terms));
  }
}

// Bounds keep every lobe value finite: the lobe base a = C . (l * v) is at
// most |Cx| + |Cy| + |Cz| <= 9 for |C| <= 3, and 9^200 ~ 1e191, so a
// trial step of the solver never overflows (Ceres rejects and logs
// non-finite residuals). rho_d in [0, 1e3]; N in [0.5, 200] (positive; N
// below 0.5 makes a lobe a near-constant); T in [0, 1e3].
constexpr double kMinN = 0.5, kMaxN = 200.0, kMaxC = 3.0, kMaxT = 1e3;

// Iteration cap of the lobe fits after the first pass (warm starts).
constexpr int kLaterPassIterations = 8;

// One Levenberg-Marquardt pass on one channel; returns iterations.
int SolveChannel(const TexelSamples& samples, const std::vector<double>& lut,
                 int channel, int lobes, const LafortuneFitOptions& fit,
                 double* x) {
  // Ceres refuses (and logs) a start whose cost is not finite; such a start
  // (a lobe power overflowing) is left as it is and the caller sees the
  // non-finite cost.
  double start_cost = 0.0;
  for (size_t i = 0; i < samples.size(); ++i) {
    const double f = LafortuneF1Channel(x, lobes, samples.l[i], samples.v[i]);
    const double d = lut[samples.view[i]] * f - samples.value[i][channel];
    start_cost += samples.weight[i][channel] * d * d;
  }
  if (!std::isfinite(start_cost)) return 0;
  ceres::Problem problem;
  problem.AddResidualBlock(
      MakeChannelCost(lobes, MakeChannelTerms(samples, lut, channel)), nullptr,
      x);
  problem.SetParameterLowerBound(x, 0, 0.0);
  problem.SetParameterUpperBound(x, 0, 1e3);
  for (int k = 0; k < lobes; ++k) {
    for (int i = 0; i < 3; ++i) {
      problem.SetParameterLowerBound(x, 1 + 4 * k + i, -kMaxC);
      problem.SetParameterUpperBound(x, 1 + 4 * k + i, kMaxC);
    }
    problem.SetParameterLowerBound(x, 4 + 4 * k, kMinN);
    problem.SetParameterUpperBound(x, 4 + 4 * k, kMaxN);
  }
  ceres::Solver::Options options;
  SetCeresLinearSolver(fit.linear_solver, &options);
  options.max_num_iterations = fit.max_iterations;
  options.function_tolerance = fit.function_tolerance;
  options.num_threads = 1;
  options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  return static_cast<int>(summary.iterations.size());
}

// The lobes of the paper's start (Section 5): grey diffuse, moderate
// highlight, slightly anisotropic lobes (Cx = 1.22 Cy for the first,
// Cy = 1.22 Cx for the second lobe).
LafortuneParams PaperStart(int lobes, double diffuse, double c) {
  LafortuneParams p;
  p.diffuse = glm::dvec3(diffuse);
  for (int k = 0; k < lobes; ++k) {
    LafortuneLobe lobe;
    const double ax = k % 2 == 0 ? 1.22 : 1.0, ay = k % 2 == 0 ? 1.0 : 1.22;
    lobe.cx = glm::dvec3(-c * ax);
    lobe.cy = glm::dvec3(-c * ay);
    lobe.cz = glm::dvec3(c);
    lobe.n = glm::dvec3(10.0);
    p.lobes.push_back(lobe);
  }
  return p;
}

// Weighted sums of the model against the data: cost, and the T update.
struct PassResult {
  double cost = 0.0;
  int iterations = 0;
};

// Fits all three channels' lobes with the given lookup table.
// With warm_channels, channels 1 and 2 start from channel 0's solution
// scaled to their data (diffuse by the ratio s of the channel sums, each
// lobe's C by s^(1/N), so its value scales by s): the channels of a texel
// share their shape, and a start next to the solution saves iterations.
PassResult FitLobes(const TexelSamples& samples,
                    const std::vector<glm::dvec3>& t,
                    const LafortuneFitOptions& options, bool warm_channels,
                    LafortuneParams* p) {
  PassResult out;
  const int lobes = static_cast<int>(p->lobes.size());
  std::vector<double> x(LafortuneChannelSize(lobes));
  glm::dvec3 sum(0.0);
  for (const glm::dvec3& y : samples.value) sum += y;
  for (int c = 0; c < 3; ++c) {
    ToArray(*p, c, x.data());
    if (warm_channels && c > 0 && sum[0] > 0.0 && sum[c] > 0.0) {
      const double scale = sum[c] / sum[0];
      ToArray(*p, 0, x.data());
      x[0] *= scale;
      for (int k = 0; k < lobes; ++k) {
        for (int i = 1; i <= 3; ++i) {
          x[4 * k + i] =
              std::clamp(x[4 * k + i] * std::pow(scale, 1.0 / x[4 * k + 4]),
                         -kMaxC, kMaxC);
        }
      }
    }
    std::vector<double> lut(t.size());
    for (size_t k = 0; k < t.size(); ++k) lut[k] = t[k][c];
    out.iterations += SolveChannel(samples, lut, c, lobes, options, x.data());
    LafortuneChannelFromArray(x.data(), c, p);
  }
  return out;
}

double Cost(const TexelSamples& s, const std::vector<glm::dvec3>& t,
            const LafortuneParams& p) {
  double cost = 0.0;
  for (size_t i = 0; i < s.size(); ++i) {
    const glm::dvec3 m = t[s.view[i]] * LafortuneF1(p, s.l[i], s.v[i]);
    const glm::dvec3 d = m - s.value[i];
    cost += glm::dot(s.weight[i] * d, d);
  }
  return std::isfinite(cost) ? cost : HUGE_VAL;
}

// Every stride-th sample of a scrambled order (Knuth's multiplicative hash
// of the index), so that the subset spreads over all views and lights;
// empty when stride <= 1 or the texel has at most kMinSubsampled samples.
constexpr size_t kMinSubsampled = 1024;
TexelSamples Subsample(const TexelSamples& samples, int stride) {
  TexelSamples sub;
  if (stride <= 1 || samples.size() <= kMinSubsampled) return sub;
  sub.normal = samples.normal;
  sub.views = samples.views;
  sub.view_alpha = samples.view_alpha;
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

// Names the first sample whose model value is not finite (issue 8): the
// table line of its first row and its directions in the texel's frame.
std::string NonFiniteSample(const TexelSamples& s,
                            const std::vector<glm::dvec3>& t,
                            const LafortuneParams& p) {
  for (size_t i = 0; i < s.size(); ++i) {
    const glm::dvec3 m = t[s.view[i]] * LafortuneF1(p, s.l[i], s.v[i]);
    if (std::isfinite(glm::dot(m - s.value[i], glm::dvec3(1.0)))) continue;
    std::ostringstream out;
    out.precision(6);
    out << "the model value is (" << m.x << ", " << m.y << ", " << m.z
        << ") at line " << s.source_line[i] << " of the table, light ("
        << s.l[i].x << ", " << s.l[i].y << ", " << s.l[i].z << ") and view ("
        << s.v[i].x << ", " << s.v[i].y << ", " << s.v[i].z
        << ") in the texel's frame";
    return out.str();
  }
  return "non-finite model values";
}

bool Finite(const LafortuneParams& p) {
  bool ok = std::isfinite(glm::dot(p.diffuse, glm::dvec3(1.0)));
  for (const LafortuneLobe& l : p.lobes) {
    ok = ok && std::isfinite(glm::dot(l.cx + l.cy + l.cz + l.n, glm::dvec3(1)));
  }
  return ok;
}

}  // namespace

ViewIndex::ViewIndex(const MeasurementTable& table) {
  std::unordered_map<std::array<long long, 6>, int, KeyHash> views, pairs;
  row_view_.resize(table.rows.size());
  row_pair_.resize(table.rows.size());
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
  }
}

TexelSamples CollectSamples(const MeasurementTable& table,
                            const ViewIndex& views,
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
    const double to_rho = table.quantity == Quantity::kBrdf ? row.wi.z : 1.0;
    const glm::dvec3 sigma = row.sigma * to_rho;
    const glm::dvec3 w = row.weight / (sigma * sigma);
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
    const double to_rho = table.quantity == Quantity::kBrdf ? row.wi.z : 1.0;
    const glm::dvec3 y = row.value * to_rho;
    const glm::dvec3 t = same_views ? model.lut.color[views.RowView(index)]
                                    : LookupView(model.lut, row.wo).color;
    const glm::dvec3 d =
        t * LafortuneF1(model.params, ToTexelFrame(frame, row.wi),
                        ToTexelFrame(frame, row.wo)) -
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

LafortuneFitResult FitLafortune(const TexelSamples& samples,
                                const LafortuneFitOptions& options) {
  LafortuneFitResult out;
  const int lobes = std::clamp(options.lobes, 0, 3);
  const size_t n_views = samples.views.size();
  std::vector<glm::dvec3> t(n_views, glm::dvec3(1.0));
  out.model.lut.views = samples.views;
  out.model.lut.alpha = samples.view_alpha;
  out.model.normal = samples.normal;
  if (samples.size() == 0) {
    out.model.params = PaperStart(lobes, 0.0, 1.0);
    out.model.lut.color = t;
    out.message = "no samples";
    return out;
  }
  // Starts: the paper's, and one scaled to the data: rho_d from the
  // weighted least squares of f1 = l.z rho_d, lobes sized so that their peak
  // c^N matches the brightest excess over it.
  glm::dvec3 num(0.0), den(0.0), peak(0.0);
  for (size_t i = 0; i < samples.size(); ++i) {
    num += samples.weight[i] * samples.value[i] * samples.l[i].z;
    den += samples.weight[i] * samples.l[i].z * samples.l[i].z;
  }
  const glm::dvec3 rho_d = glm::dvec3(den.x > 0 ? num.x / den.x : 0.0,
                                      den.y > 0 ? num.y / den.y : 0.0,
                                      den.z > 0 ? num.z / den.z : 0.0);
  for (size_t i = 0; i < samples.size(); ++i) {
    const glm::dvec3 excess =
        samples.value[i] / std::max(samples.l[i].z, 1e-3) - rho_d;
    peak = glm::max(peak, excess);
  }
  // A warm start (the best of a group's children), else the paper's.
  const LafortuneModel* warm = nullptr;
  double warm_cost = HUGE_VAL;
  for (const LafortuneModel* m : options.warm_starts) {
    if (m == nullptr || static_cast<int>(m->params.lobes.size()) != lobes ||
        m->lut.color.size() != n_views) {
      continue;
    }
    const double cost =
        Cost(samples, options.lookup_table ? m->lut.color : t, m->params);
    if (cost < warm_cost) {
      warm_cost = cost;
      warm = m;
    }
  }
  if (warm != nullptr && options.lookup_table) t = warm->lut.color;
  // A given start (--init) with this lobe count, and its lookup table when
  // it was fitted on the same views.
  const LafortuneModel* given =
      warm == nullptr && options.start != nullptr &&
              static_cast<int>(options.start->params.lobes.size()) == lobes
          ? options.start
          : nullptr;
  if (given != nullptr && options.lookup_table &&
      given->lut.views.size() == n_views &&
      given->lut.color.size() == n_views) {
    bool same_views = true;
    for (size_t k = 0; k < n_views && same_views; ++k) {
      same_views = glm::length(given->lut.views[k] - samples.views[k]) <= 1e-9;
    }
    if (same_views) t = given->lut.color;
  }
  std::vector<LafortuneParams> starts = {warm != nullptr ? warm->params
                                         : given != nullptr
                                             ? given->params
                                             : PaperStart(lobes, 0.5, 1.0)};
  if (options.data_driven_start && warm == nullptr) {
    const double mean_peak = std::max((peak.x + peak.y + peak.z) / 3.0, 1e-6);
    LafortuneParams d = PaperStart(lobes, 0.0, std::pow(mean_peak, 0.1));
    d.diffuse = glm::max(0.7 * rho_d, glm::dvec3(0.0));
    starts.push_back(d);
  }
  LafortuneParams best;
  double best_cost = HUGE_VAL;
  // The first pass (from a start far from the solution, most of the
  // iterations) runs on a subsample; the later passes refine on all samples.
  const TexelSamples sub = Subsample(samples, options.first_pass_subsample);
  const TexelSamples& first = sub.size() > 0 ? sub : samples;
  for (LafortuneParams p : starts) {
    out.iterations +=
        FitLobes(first, t, options, options.warm_channels, &p).iterations;
    const double cost = Cost(samples, t, p);
    if (Finite(p) && cost < best_cost) {
      best_cost = cost;
      best = p;
    }
  }
  if (!(best_cost < HUGE_VAL)) {
    out.model.params = starts.front();
    out.model.lut.color = t;
    out.message = "the lobe fit produced no finite solution";
    return out;
  }
  out.alternations = 1;
  // Alternation: T in closed form per view and channel (eq. 4), then the
  // lobes again, until the mean relative change of T is small.
  bool lut_converged = false;
  if (options.lookup_table) {
    for (int pass = 1; pass < options.max_alternations; ++pass) {
      std::vector<glm::dvec3> fr(n_views, glm::dvec3(0.0)),
          ff(n_views, glm::dvec3(0.0));
      for (size_t i = 0; i < samples.size(); ++i) {
        const glm::dvec3 f = LafortuneF1(best, samples.l[i], samples.v[i]);
        fr[samples.view[i]] += samples.weight[i] * f * samples.value[i];
        ff[samples.view[i]] += samples.weight[i] * f * f;
      }
      // A view whose f is (nearly) zero carries no information on T: keep
      // it rather than divide by ~0. T is a non-negative factor; it is kept
      // in [0, kMaxT].
      glm::dvec3 ff_max(0.0);
      for (const glm::dvec3& f : ff) ff_max = glm::max(ff_max, f);
      double change = 0.0;
      int counted = 0;
      for (size_t k = 0; k < n_views; ++k) {
        for (int c = 0; c < 3; ++c) {
          if (!(ff[k][c] > 1e-12 * ff_max[c])) continue;  // no signal
          const double updated = std::clamp(fr[k][c] / ff[k][c], 0.0, kMaxT);
          change +=
              std::abs(updated - t[k][c]) / std::max(std::abs(t[k][c]), 1e-12);
          ++counted;
          t[k][c] = updated;
        }
      }
      out.lut_change = counted ? change / counted : 0.0;
      // Later passes start next to their solution: a few iterations do.
      LafortuneFitOptions later = options;
      later.max_iterations =
          std::min(options.max_iterations, kLaterPassIterations);
      LafortuneParams p = best;
      out.iterations += FitLobes(samples, t, later, false, &p).iterations;
      ++out.alternations;
      if (Finite(p)) best = p;
      if (out.lut_change < options.lut_threshold) {
        lut_converged = true;
        break;
      }
    }
  }
  if (!options.lookup_table) {
    out.converged = true;
    out.termination = "no lookup table: one lobe fit";
  } else if (lut_converged) {
    out.converged = true;
    out.termination = "lookup table converged";
  } else {
    char why[160];
    std::snprintf(why, sizeof(why),
                  "alternation cap (%d) reached; the lookup table still "
                  "changed by %.3g (threshold %.3g)",
                  options.max_alternations, out.lut_change,
                  options.lut_threshold);
    out.termination = why;
  }
  // A first pass on a subsample is refined on all samples when no later
  // pass did (no lookup table, or a single alternation): a lobe fitted to a
  // quarter of the samples alone can be narrow and wrong between them.
  if (&first != &samples && out.alternations == 1) {
    LafortuneParams p = best;
    out.iterations += FitLobes(samples, t, options, false, &p).iterations;
    if (Finite(p)) best = p;
  }
  out.model.params = best;
  out.model.lut.color = t;
  double se = 0.0, ss = 0.0;
  for (size_t i = 0; i < samples.size(); ++i) {
    const glm::dvec3 m =
        t[samples.view[i]] * LafortuneF1(best, samples.l[i], samples.v[i]);
    const glm::dvec3 d = m - samples.value[i];
    se += glm::dot(d, d);
    ss += glm::dot(samples.value[i], samples.value[i]);
  }
  out.final_cost = 0.5 * Cost(samples, t, best);
  out.rms = std::sqrt(se / (3.0 * samples.size()));
  out.relative_rms = ss > 0.0 ? std::sqrt(se / ss) : 0.0;
  out.usable = std::isfinite(out.rms);
  if (!out.usable) out.message = NonFiniteSample(samples, t, best);
  return out;
}

}  // namespace clothfit
