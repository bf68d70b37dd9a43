#include "fitting/cloth_fit.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>

#include "fitting/least_squares.h"
#include "fitting/start_search.h"
#include "io/input_error.h"
#include "io/text_util.h"
#include "models/evaluate.h"

namespace clothfit {
namespace {

// Parameter vector: per thread j, the ThreadParams layout (7 entries) then
// [coverage, offset_scale]; the thread's tangent offsets are offset_scale
// times the initial ones. Ceres sees one block per thread's ThreadParams
// and, only when some coverage or offset_scale is free, one [coverage,
// offset_scale] block per thread: fewer Jet lanes when they are fixed.
constexpr int kWeaveSize = 2;
constexpr int kPerThread = ThreadParams::kSize + kWeaveSize;

// What stays fixed through a fit, shared by all residuals.
struct Weave {
  ClothParams layout;          // directions, base offsets, fixed values
  bool weave_blocks = false;   // coverage/offset_scale blocks passed to Ceres
  bool shared_albedo = false;  // every thread uses thread 0's albedo
  bool fit_scale = false;      // a last block [scale] multiplies the model
};

// The tangent samples of one row, computed once when the directions and the
// tangent offsets are fixed; with eta fixed, their Fresnel terms too. Then
// only the parameter-dependent part of the thread BSDF needs Jets.
struct RowSamples {
  std::vector<std::vector<TangentSample<double>>> per_thread;
  // per_thread[j][k]'s Fresnel term; empty for a thread whose eta is free.
  std::vector<std::vector<double>> fresnel;

  int Count(size_t j) const { return static_cast<int>(per_thread[j].size()); }
  const TangentSample<double>& Get(size_t j, int k) const {
    return per_thread[j][k];
  }
  template <typename T>
  ThreadLobes<T> Lobes(size_t j, int k, const TangentSample<double>& sample,
                       const ThreadParamsT<T>& params) const {
    if (fresnel[j].empty()) return ThreadLobesOf(sample.geometry, params);
    return ThreadLobesGivenFresnel(sample.geometry, fresnel[j][k], params);
  }
};

RowSamples ComputeRowSamples(const ClothParams& layout,
                             const std::vector<bool>& eta_fixed,
                             const TableRow& row) {
  RowSamples out;
  out.per_thread.resize(layout.threads.size());
  out.fresnel.resize(layout.threads.size());
  if (!IsReflectionRow(row)) return out;  // reflection only
  for (size_t j = 0; j < layout.threads.size(); ++j) {
    const ClothThread& th = layout.threads[j];
    for (double offset : th.offsets_deg) {
      const TangentSample<double> sample =
          ComputeTangentSample(th.direction, offset, row.wi, row.wo);
      out.per_thread[j].push_back(sample);
      if (eta_fixed[j]) {
        out.fresnel[j].push_back(
            sample.valid ? ThreadFresnel(sample.geometry, th.params.eta) : 0.0);
      }
    }
  }
  return out;
}

// The cloth described by Ceres' blocks (see kPerThread).
template <typename T>
ClothParamsT<T> ClothFromBlocks(const Weave& weave, const T* const* blocks,
                                bool with_offsets) {
  const size_t n = weave.layout.threads.size();
  const int stride = weave.weave_blocks ? 2 : 1;
  ClothParamsT<T> c;
  c.threads.resize(n);
  for (size_t j = 0; j < n; ++j) {
    const ClothThread& base = weave.layout.threads[j];
    ClothThreadT<T>& th = c.threads[j];
    th.direction = base.direction;
    th.params = ThreadParamsFromArray(blocks[stride * j]);
    if (weave.shared_albedo) {
      th.params.albedo = Vec3<T>(blocks[0][4], blocks[0][5], blocks[0][6]);
    }
    const T* w = weave.weave_blocks ? blocks[stride * j + 1] : nullptr;
    th.coverage = w ? w[0] : T(base.coverage);
    if (with_offsets) {
      th.offsets_deg.resize(base.offsets_deg.size());
      for (size_t k = 0; k < base.offsets_deg.size(); ++k) {
        th.offsets_deg[k] = (w ? w[1] : T(1.0)) * T(base.offsets_deg[k]);
      }
    }
  }
  return c;
}

// residual_c = (s model_c - measured_c) sqrt(weight) / sigma_c, c <
// kChannels; s = 1 or, with fit_scale, a last block [s]. Ceres passes one
// block per thread (two with weave blocks), 1 to 3 threads, (+ the scale):
// one call operator per block count, 1 to 7.
template <int kChannels>
struct ClothResidual {
  std::shared_ptr<const Weave> weave;
  glm::dvec3 wi, wo, value, scale;
  Quantity quantity;
  // Set when the offsets are fixed: the row's samples, computed once.
  std::shared_ptr<const RowSamples> samples;

  template <typename T>
  bool Residual(const T* const* blocks, T* residual) const {
    Vec3<T> model;
    if (samples) {
      model = FromCosineWeighted(
          ClothRhoFromSamples(ClothFromBlocks(*weave, blocks, false), *samples,
                              wi.z),
          wi.z, quantity);
    } else {
      model = ClothValue(ClothFromBlocks(*weave, blocks, true), Cast<T>(wi),
                         Cast<T>(wo), quantity);
    }
    const size_t n = weave->layout.threads.size();
    const T s = weave->fit_scale ? blocks[n * (weave->weave_blocks ? 2 : 1)][0]
                                 : T(1.0);
    for (int c = 0; c < kChannels; ++c) {
      residual[c] = (s * model[c] - T(value[c])) * T(scale[c]);
    }
    return true;
  }
  template <typename T>
  bool operator()(const T* b0, T* r) const {
    const T* const b[] = {b0};
    return Residual(b, r);
  }
  template <typename T>
  bool operator()(const T* b0, const T* b1, T* r) const {
    const T* const b[] = {b0, b1};
    return Residual(b, r);
  }
  template <typename T>
  bool operator()(const T* b0, const T* b1, const T* b2, T* r) const {
    const T* const b[] = {b0, b1, b2};
    return Residual(b, r);
  }
  template <typename T>
  bool operator()(const T* b0, const T* b1, const T* b2, const T* b3,
                  T* r) const {
    const T* const b[] = {b0, b1, b2, b3};
    return Residual(b, r);
  }
  template <typename T>
  bool operator()(const T* b0, const T* b1, const T* b2, const T* b3,
                  const T* b4, T* r) const {
    const T* const b[] = {b0, b1, b2, b3, b4};
    return Residual(b, r);
  }
  template <typename T>
  bool operator()(const T* b0, const T* b1, const T* b2, const T* b3,
                  const T* b4, const T* b5, T* r) const {
    const T* const b[] = {b0, b1, b2, b3, b4, b5};
    return Residual(b, r);
  }
  template <typename T>
  bool operator()(const T* b0, const T* b1, const T* b2, const T* b3,
                  const T* b4, const T* b5, const T* b6, T* r) const {
    const T* const b[] = {b0, b1, b2, b3, b4, b5, b6};
    return Residual(b, r);
  }

  // AutoDiffCostFunction over the blocks (sizes...).
  template <int... kSizes>
  static ceres::CostFunction* Make(ClothResidual* f) {
    return new ceres::AutoDiffCostFunction<ClothResidual, kChannels, kSizes...>(
        f);
  }

  static ceres::CostFunction* Create(
      std::shared_ptr<const Weave> weave, const TableRow& row,
      Quantity quantity, std::shared_ptr<const RowSamples> samples) {
    constexpr int P = ThreadParams::kSize, W = kWeaveSize;
    const size_t n = weave->layout.threads.size();
    const int layout = static_cast<int>(n) * 4 + (weave->weave_blocks ? 2 : 0) +
                       (weave->fit_scale ? 1 : 0);
    auto* f = new ClothResidual{std::move(weave),
                                row.wi,
                                row.wo,
                                row.value,
                                std::sqrt(row.weight) / row.sigma,
                                quantity,
                                std::move(samples)};
    switch (layout) {  // threads * 4 + weave blocks * 2 + scale
      case 4:
        return Make<P>(f);
      case 5:
        return Make<P, 1>(f);
      case 6:
        return Make<P, W>(f);
      case 7:
        return Make<P, W, 1>(f);
      case 8:
        return Make<P, P>(f);
      case 9:
        return Make<P, P, 1>(f);
      case 10:
        return Make<P, W, P, W>(f);
      case 11:
        return Make<P, W, P, W, 1>(f);
      case 12:
        return Make<P, P, P>(f);
      case 13:
        return Make<P, P, P, 1>(f);
      case 14:
        return Make<P, W, P, W, P, W>(f);
      default:
        return Make<P, W, P, W, P, W, 1>(f);
    }
  }
};

std::vector<ParameterSpec> ClothSpecs(const ClothParams& layout) {
  std::vector<ParameterSpec> specs;
  const char* const* names = ThreadParamNames();
  const double lower[] = {1.01, 0.0, 0.2, 0.2, 0.0, 0.0, 0.0};
  const double upper[] = {3.0, 1.0, 90.0, 90.0, 1e3, 1e3, 1e3};
  for (size_t j = 0; j < layout.threads.size(); ++j) {
    const std::string prefix = "threads[" + std::to_string(j) + "].";
    for (int i = 0; i < ThreadParams::kSize; ++i) {
      // eta is fixed by default: the data rarely separate it from kd/albedo.
      const bool free = i != 0;
      // kd and the albedo are bounded by their physical range.
      specs.push_back(
          {prefix + names[i], lower[i], upper[i], free, i == 1 || i >= 4});
    }
    double largest = 0.0;
    for (double o : layout.threads[j].offsets_deg) {
      largest = std::max(largest, std::abs(o));
    }
    specs.push_back({prefix + "coverage", 0.0, 1.0, false, true});
    specs.push_back({prefix + "offset_scale", 0.0,
                     largest > 0.0 ? 90.0 / largest : 1.0, false});
  }
  specs.push_back({"scale", 1e-6, 1e6, false});
  return specs;
}

// Per thread kPerThread entries, then the scale (1).
std::vector<double> ToVector(const ClothParams& c) {
  std::vector<double> x;
  for (const ClothThread& th : c.threads) {
    double p[ThreadParams::kSize];
    ToArray(th.params, p);
    x.insert(x.end(), p, p + ThreadParams::kSize);
    x.push_back(th.coverage);
    x.push_back(1.0);  // offset_scale relative to the layout
  }
  x.push_back(1.0);  // scale
  return x;
}

ClothParams FromVector(const ClothParams& layout, const std::vector<double>& x,
                       bool shared_albedo) {
  ClothParams c = layout;
  for (size_t j = 0; j < c.threads.size(); ++j) {
    const double* t = x.data() + j * kPerThread;
    c.threads[j].params = ThreadParamsFromArray(t);
    if (shared_albedo) {
      c.threads[j].params.albedo = glm::dvec3(x[4], x[5], x[6]);
    }
    c.threads[j].coverage = t[ThreadParams::kSize];
    for (double& o : c.threads[j].offsets_deg) o *= t[ThreadParams::kSize + 1];
  }
  return c;
}

// Values of the model over the table, per row and channel.
using Values = std::vector<glm::dvec3>;

Values Predict(const MeasurementTable& table, const ClothParams& c,
               const std::vector<std::shared_ptr<const RowSamples>>& samples) {
  Values out(table.rows.size());
  for (size_t i = 0; i < table.rows.size(); ++i) {
    const TableRow& row = table.rows[i];
    out[i] = samples[i] ? FromCosineWeighted(
                              ClothRhoFromSamples(c, *samples[i], row.wi.z),
                              row.wi.z, table.quantity)
                        : ClothValue(c, row.wi, row.wo, table.quantity);
  }
  return out;
}

}  // namespace

ClothParams GenericClothStart(const ClothParams& weave) {
  ClothParams c = weave;
  for (ClothThread& th : c.threads) {
    th.params.kd = 0.3;
    th.params.gamma_s_deg = 10.0;
    th.params.gamma_v_deg = 20.0;
    th.params.albedo = glm::dvec3(0.1);
  }
  return c;
}

std::vector<std::string> ClothParameterNames(const ClothParams& layout) {
  std::vector<std::string> names;
  for (const ParameterSpec& s : ClothSpecs(layout)) names.push_back(s.name);
  return names;
}

std::vector<double> ClothParameterValues(const ClothParams& c,
                                         const ClothParams& layout) {
  std::vector<double> x = ToVector(c);
  for (size_t j = 0; j < c.threads.size() && j < layout.threads.size(); ++j) {
    double mine = 0.0, theirs = 0.0;
    for (double o : c.threads[j].offsets_deg)
      mine = std::max(mine, std::abs(o));
    for (double o : layout.threads[j].offsets_deg) {
      theirs = std::max(theirs, std::abs(o));
    }
    x[j * kPerThread + ThreadParams::kSize + 1] =
        theirs > 0.0 ? mine / theirs : 1.0;
  }
  return x;
}

ClothFitResult FitCloth(const MeasurementTable& table, const ClothParams& init,
                        const ClothFitOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();  // search + solves
  if (table.quantity == Quantity::kTransmittance) {
    throw InputError(
        "a cloth model predicts brdf or cosine_weighted values, "
        "not transmittance");
  }
  if (init.threads.empty() || init.threads.size() > 3) {
    throw InputError(
        "cloth fit: the initial parameters need 1 to 3 threads, got " +
        std::to_string(init.threads.size()));
  }
  // The cloth model is reflection only (SPEC §3.2): a row with the light or
  // the view below the surface tells nothing about it. Such rows are left
  // out and counted, not fitted as zeros.
  const size_t not_reflection = static_cast<size_t>(
      std::count_if(table.rows.begin(), table.rows.end(),
                    [](const TableRow& row) { return !IsReflectionRow(row); }));
  if (not_reflection == table.rows.size()) {
    throw InputError(
        "cloth fit: no row has both the light and the view above the "
        "surface (the cloth model is reflection only)");
  }
  if (not_reflection > 0) {
    MeasurementTable reflection = table;
    reflection.rows.erase(
        std::remove_if(
            reflection.rows.begin(), reflection.rows.end(),
            [](const TableRow& row) { return !IsReflectionRow(row); }),
        reflection.rows.end());
    ClothFitResult result = FitCloth(reflection, init, options);
    result.report.rows_not_used = static_cast<int>(not_reflection);
    return result;
  }
  const size_t n = init.threads.size();
  LeastSquaresProblem lsq;
  lsq.specs = ClothSpecs(init);
  ApplyFreeFix(options.fix, options.free_only, &lsq.specs);
  if (table.channels == 1) {  // one channel: albedo_g, albedo_b follow r
    for (size_t j = 0; j < init.threads.size(); ++j) {
      lsq.specs[j * kPerThread + 5].free = false;
      lsq.specs[j * kPerThread + 6].free = false;
    }
  }
  // Entry i of thread j's part of the vector (ThreadParams layout, then 7:
  // coverage, 8: offset_scale).
  auto is_free = [&](size_t j, int i) {
    return lsq.specs[j * kPerThread + i].free;
  };
  constexpr int kEta = 0, kKd = 1, kGammaS = 2, kGammaV = 3, kAlbedo = 4;
  constexpr int kCoverage = 7, kOffsetScale = 8;
  auto weave = std::make_shared<Weave>();
  weave->layout = init;
  weave->shared_albedo = options.shared_albedo && n > 1;
  if (weave->shared_albedo) {  // threads j > 0 take thread 0's albedo
    for (size_t j = 1; j < n; ++j) {
      for (int c = 0; c < 3; ++c)
        lsq.specs[j * kPerThread + 4 + c].free = false;
    }
  }
  bool offsets_fixed = true;
  std::vector<bool> eta_fixed(n);
  for (size_t j = 0; j < n; ++j) {
    weave->weave_blocks = weave->weave_blocks || is_free(j, kCoverage) ||
                          is_free(j, kOffsetScale);
    offsets_fixed = offsets_fixed && !is_free(j, kOffsetScale);
    eta_fixed[j] = !is_free(j, kEta);
  }
  // Ceres blocks: [thread j params] (+ [weave j]) in vector order; the
  // weave entries that Ceres does not see stay at their initial values.
  for (size_t j = 0; j < n; ++j) {
    lsq.block_sizes.push_back(ThreadParams::kSize);
    lsq.block_sizes.push_back(kWeaveSize);
  }
  lsq.block_sizes.push_back(1);
  lsq.specs.back().free = options.fit_scale;
  weave->fit_scale = options.fit_scale;
  lsq.sigma_known = table.has_sigma;

  // With every offset_scale fixed the tangent samples never change: compute
  // them once for all starts and solves.
  std::vector<std::shared_ptr<const RowSamples>> row_samples(table.rows.size());
  if (offsets_fixed) {
    for (size_t i = 0; i < table.rows.size(); ++i) {
      row_samples[i] = std::make_shared<const RowSamples>(
          ComputeRowSamples(init, eta_fixed, table.rows[i]));
    }
  }
  lsq.add_residuals = [&](const std::vector<double*>& blocks,
                          ceres::LossFunction* loss, ceres::Problem* problem) {
    std::vector<double*> used;
    for (size_t j = 0; j < n; ++j) {
      used.push_back(blocks[2 * j]);
      if (weave->weave_blocks) used.push_back(blocks[2 * j + 1]);
    }
    if (weave->fit_scale) used.push_back(blocks.back());
    for (size_t i = 0; i < table.rows.size(); ++i) {
      const TableRow& row = table.rows[i];
      ceres::CostFunction* cost =
          table.channels == 1 ? ClothResidual<1>::Create(
                                    weave, row, table.quantity, row_samples[i])
                              : ClothResidual<3>::Create(
                                    weave, row, table.quantity, row_samples[i]);
      problem->AddResidualBlock(cost, loss, used);
    }
  };
  lsq.predict = [&](const std::vector<double>& x, std::vector<double>* model,
                    std::vector<double>* measured,
                    std::vector<const TableRow*>* rows) {
    const Values v =
        Predict(table, FromVector(init, x, weave->shared_albedo), row_samples);
    for (size_t i = 0; i < table.rows.size(); ++i) {
      for (int ch = 0; ch < table.channels; ++ch) {
        model->push_back(x.back() * v[i][ch]);
        measured->push_back(table.rows[i].value[ch]);
        if (rows) rows->push_back(&table.rows[i]);
      }
    }
  };

  // Starts: a grid search over each thread's widths (and eta) with the
  // linear parameters (albedo, kd, scale) solved in closed form, by
  // coordinate descent over the threads (fitting/start_search.h). It needs
  // each thread's contribution a_j S_j / Q per row, with the tangent
  // samples and Q of the initial weave.
  std::vector<std::shared_ptr<const RowSamples>> search_samples = row_samples;
  for (size_t i = 0; i < table.rows.size(); ++i) {
    if (!search_samples[i]) {
      search_samples[i] = std::make_shared<const RowSamples>(
          ComputeRowSamples(init, eta_fixed, table.rows[i]));
    }
  }
  std::vector<double> inv_q(table.rows.size(), 0.0);  // 1 / Q, 0 if Q <= 0
  for (size_t i = 0; i < table.rows.size(); ++i) {
    double q = 0.0, coverage = 0.0;
    for (size_t j = 0; j < n; ++j) {
      Vec3<double> s_j;
      double w_j;
      ThreadSums(init.threads[j].params, *search_samples[i], j, &s_j, &w_j);
      q += init.threads[j].coverage * w_j;
      coverage += init.threads[j].coverage;
    }
    q += (1.0 - coverage) * table.rows[i].wi.z;
    inv_q[i] = q > 0.0 ? 1.0 / q : 0.0;
  }
  StartSearchProblem search;
  search.table = &table;
  search.contribution = [&](size_t j, const ThreadParams& p) {
    RowValues v(table.rows.size());
    const double coverage = init.threads[j].coverage;
    for (size_t i = 0; i < v.size(); ++i) {
      Vec3<double> s_j;
      double w_j;
      ThreadSums(p, *search_samples[i], j, &s_j, &w_j);
      v[i] = FromCosineWeighted(s_j * (coverage * inv_q[i]), table.rows[i].wi.z,
                                table.quantity);
    }
    return v;
  };
  search.shared_albedo = weave->shared_albedo;
  search.fit_scale = options.fit_scale;
  for (size_t j = 0; j < n; ++j) {
    search.init.push_back(init.threads[j].params);
    search.kd_free.push_back(is_free(j, kKd));
    search.gamma_s_free.push_back(is_free(j, kGammaS));
    search.gamma_v_free.push_back(is_free(j, kGammaV));
    // A shared albedo is thread 0's (the others' entries are fixed).
    const size_t owner = weave->shared_albedo ? 0 : j;
    search.albedo_free.push_back(is_free(owner, kAlbedo) ||
                                 is_free(owner, kAlbedo + 1) ||
                                 is_free(owner, kAlbedo + 2));
  }
  if (!options.multi_start) {  // one start: the init
    for (size_t j = 0; j < n; ++j) {
      search.gamma_s_free[j] = search.gamma_v_free[j] = false;
    }
  }
  std::vector<std::vector<double>> starts;
  for (const StartPoint& point :
       SearchStarts(search, std::max(1, options.solve_starts))) {
    ClothParams c = init;
    for (size_t j = 0; j < n; ++j) c.threads[j].params = point.threads[j];
    std::vector<double> x = ToVector(c);
    x.back() = point.scale;
    starts.push_back(x);
  }

  ClothFitResult result;
  std::vector<double> x = starts.front();
  result.report = SolveLeastSquares(lsq, starts, options.solver, &x);
  result.params = FromVector(init, x, weave->shared_albedo);
  if (weave->shared_albedo) {  // report the tied albedos at their value
    for (ParameterReport& p : result.report.parameters) {
      for (const char* channel : {"albedo_r", "albedo_g", "albedo_b"}) {
        if (text_util::EndsWith(p.name, std::string(".") + channel)) {
          p.value = x[4 + (channel[7] == 'r' ? 0 : channel[7] == 'g' ? 1 : 2)];
        }
      }
    }
  }
  if (table.channels == 1) {
    for (ClothThread& th : result.params.threads) {
      th.params.albedo = glm::dvec3(th.params.albedo.x);
    }
    ReportChannelsFollowRed("albedo", &result.report);
  }
  result.report.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0)
          .count();
  return result;
}

}  // namespace clothfit
