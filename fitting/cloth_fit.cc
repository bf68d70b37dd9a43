#include "fitting/cloth_fit.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>

#include "fitting/least_squares.h"
#include "fitting/model_residual_internal.h"
#include "fitting/start_search.h"
#include "io/input_error.h"
#include "io/text_util.h"
#include "models/evaluate.h"

namespace clothfit {
namespace {

// Parameter vector: per thread j, the thread's table (7 entries) then
// [coverage, offset_scale]; the thread's tangent offsets are offset_scale
// times the initial ones. Then the scale. Ceres sees one block per
// thread's parameters and, only when some coverage or offset_scale is
// free, one [coverage, offset_scale] block per thread.
constexpr int kWeaveSize = 2;
constexpr int kPerThread = kThreadFlatSize + kWeaveSize;

// What stays fixed through a fit, shared by all residuals.
struct Weave {
  ClothParams layout;          // directions, base offsets, fixed values
  bool weave_blocks = false;   // coverage/offset_scale blocks passed to Ceres
  bool shared_albedo = false;  // every thread uses thread 0's albedo
  // Free coverages that sum to at most 1, by stick-breaking (the threads
  // s_0, s_1, ... in order): the solver's entry u_k in [0, 1] gives
  // a_{s_k} = R u_k prod_{i<k} (1 - u_i), R = 1 - the fixed coverages'
  // sum (at least 0). Box bounds on u, no clipping of a; empty: no
  // coverage is free.
  std::vector<size_t> stick;
  double remaining = 1.0;
};

// The index of thread j's coverage in the flat vector.
constexpr size_t CoverageEntry(size_t j) {
  return j * kPerThread + kThreadFlatSize;
}

// The coverages a of the stick-breaking entries u of x (Weave::stick), in
// any scalar type: `coverage(j)` reads and writes thread j's entry.
template <typename T, typename Coverage>
void StickToCoverage(const Weave& weave, const Coverage& coverage) {
  T left(weave.remaining);
  for (size_t j : weave.stick) {
    T& entry = coverage(j);
    const T u = entry;
    entry = left * u;
    left = left * (T(1.0) - u);
  }
}

// x with the stick entries as coverages (what the report and the
// parameter file give), and its inverse, a start's coverages as stick
// entries (moved into [0, 1]).
std::vector<double> StickToCoverage(const Weave& weave, std::vector<double> x) {
  StickToCoverage<double>(
      weave, [&](size_t j) -> double& { return x[CoverageEntry(j)]; });
  return x;
}
std::vector<double> CoverageToStick(const Weave& weave, std::vector<double> x) {
  double left = weave.remaining;
  for (size_t j : weave.stick) {
    double& entry = x[CoverageEntry(j)];
    const double u = left > 0.0 ? std::clamp(entry / left, 0.0, 1.0) : 0.0;
    entry = u;
    left *= 1.0 - u;
  }
  return x;
}

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
    FromArray(blocks[stride * j], &th.params);
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
  StickToCoverage<T>(weave,
                     [&](size_t j) -> T& { return c.threads[j].coverage; });
  return c;
}

// The cloth's value at row i: the blocks are, per thread, its parameters
// and (with weave blocks) its [coverage, offset_scale]. With the offsets
// fixed the row's tangent samples were computed once (`samples`);
// otherwise they follow the blocks.
struct ClothEvaluator {
  const MeasurementTable* table;
  std::shared_ptr<const Weave> weave;
  std::vector<std::shared_ptr<const RowSamples>> samples;  // per row, or null

  template <typename T>
  Vec3<T> operator()(const T* const* blocks, size_t i) const {
    const TableRow& row = table->rows[i];
    if (samples[i]) {
      return ConvertQuantity(
          ClothRhoFromSamples(ClothFromBlocks(*weave, blocks, false),
                              *samples[i], row.wi.z),
          Quantity::kCosineWeighted, table->quantity, row.wi.z);
    }
    return Value(ClothFromBlocks(*weave, blocks, true), row.wi, row.wo,
                 table->quantity);
  }
};

// The fit-only entry of a thread: a factor on all of its tangent offsets,
// keeping the weave's shape; bounded so that the largest offset stays
// within [-90, 90] degrees.
inline constexpr ParamInfo kOffsetScale = {
    "offset_scale",
    "unitless",
    "factor on all of a thread's tangent offsets (the weave's shape kept)",
    {0.0, kInfinity},
    0.0,
    1.0,
    false,
    {1.0},
    "clothfit",
    1};

std::vector<ParameterSpec> ClothSpecs(const ClothParams& layout) {
  std::vector<ParameterSpec> specs;
  for (size_t j = 0; j < layout.threads.size(); ++j) {
    const std::string prefix = ClothThreadPrefix(j);
    for (ParameterSpec& spec : ParameterSpecs(ThreadParams(), prefix)) {
      specs.push_back(spec);
    }
    // eta is fixed by default: the data rarely separate it from kd/albedo.
    specs[specs.size() - kThreadFlatSize].free = false;
    double largest = 0.0;
    for (double o : layout.threads[j].offsets_deg) {
      largest = std::max(largest, std::abs(o));
    }
    specs.push_back(SpecOf(kClothCoverage, prefix + kClothCoverage.name));
    specs.back().free = false;
    ParameterSpec offsets = SpecOf(kOffsetScale, prefix + kOffsetScale.name);
    offsets.upper = largest > 0.0 ? kClothOffsets.fit_hi / largest : 1.0;
    offsets.free = false;
    specs.push_back(offsets);
  }
  specs.push_back(SpecOf(kFitScale, kFitScale.name));
  specs.back().free = false;
  return specs;
}

// Per thread kPerThread entries, then the scale (1).
std::vector<double> ToVector(const ClothParams& c) {
  std::vector<double> x;
  for (const ClothThread& th : c.threads) {
    double p[kThreadFlatSize];
    ToArray(th.params, p);
    x.insert(x.end(), p, p + kThreadFlatSize);
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
    FromArray(t, &c.threads[j].params);
    if (shared_albedo) {
      c.threads[j].params.albedo = glm::dvec3(x[4], x[5], x[6]);
    }
    c.threads[j].coverage = t[kThreadFlatSize];
    for (double& o : c.threads[j].offsets_deg) o *= t[kThreadFlatSize + 1];
  }
  c.scale = x.back();  // 1 unless fitted (--fit-scale)
  return c;
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
    x[j * kPerThread + kThreadFlatSize + 1] =
        theirs > 0.0 ? mine / theirs : 1.0;
  }
  return x;
}

ClothFitResult FitCloth(const MeasurementTable& table, const ClothParams& init,
                        const ClothFitOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();  // search + solves
  RequireWeightedRows(table);
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
  const int not_reflection = CountNotReflection(table, "cloth");
  if (not_reflection > 0) {
    MeasurementTable reflection = table;
    reflection.rows.erase(
        std::remove_if(
            reflection.rows.begin(), reflection.rows.end(),
            [](const TableRow& row) { return !IsReflectionRow(row); }),
        reflection.rows.end());
    ClothFitResult result = FitCloth(reflection, init, options);
    result.report.rows_not_used = not_reflection;
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
  double fixed_coverage = 0.0;
  for (size_t j = 0; j < n; ++j) {
    if (is_free(j, kCoverage)) {
      weave->stick.push_back(j);
    } else {
      fixed_coverage += init.threads[j].coverage;
    }
  }
  weave->remaining = std::max(0.0, 1.0 - fixed_coverage);
  if (!weave->stick.empty()) {
    lsq.reported = [weave](const std::vector<double>& x) {
      return StickToCoverage(*weave, x);
    };
  }
  // Ceres blocks: [thread j params] (+ [weave j]) in vector order; the
  // weave entries that Ceres does not see stay at their initial values.
  for (size_t j = 0; j < n; ++j) {
    lsq.block_sizes.push_back(kThreadFlatSize);
    lsq.block_sizes.push_back(kWeaveSize);
  }
  lsq.block_sizes.push_back(1);
  lsq.specs.back().free = options.fit_scale;
  const Weighting weighting(table, options.solver.noise);
  lsq.sigma_known = weighting.LevelKnown();

  // With every offset_scale fixed the tangent samples never change: compute
  // them once for all starts and solves.
  auto evaluator = std::make_shared<ClothEvaluator>();
  evaluator->table = &table;
  evaluator->weave = weave;
  evaluator->samples.resize(table.rows.size());
  if (offsets_fixed) {
    for (size_t i = 0; i < table.rows.size(); ++i) {
      evaluator->samples[i] = std::make_shared<const RowSamples>(
          ComputeRowSamples(init, eta_fixed, table.rows[i]));
    }
  }
  ResidualBlocks blocks;
  for (size_t j = 0; j < n; ++j) {
    blocks.used.push_back(static_cast<int>(2 * j));
    if (weave->weave_blocks) blocks.used.push_back(static_cast<int>(2 * j + 1));
  }
  if (options.fit_scale) {
    blocks.scale = static_cast<int>(blocks.used.size());
    blocks.used.push_back(static_cast<int>(2 * n));
  }
  const std::vector<std::shared_ptr<const RowSamples>>& row_samples =
      evaluator->samples;
  SetModelResiduals(std::shared_ptr<const ClothEvaluator>(evaluator),
                    TableFitRows(table, weighting), blocks, &lsq);

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
    ClothNormalisation<double> normalisation;
    for (size_t j = 0; j < n; ++j) {
      Vec3<double> s_j;
      double w_j;
      ThreadSums(init.threads[j].params, *search_samples[i], j, &s_j, &w_j);
      normalisation.Add(init.threads[j].coverage, w_j);
    }
    const double q = normalisation.Q(table.rows[i].wi.z);
    inv_q[i] = q > 0.0 ? 1.0 / q : 0.0;
  }
  StartSearchProblem search;
  search.table = &table;
  search.weighting = &weighting;
  search.contribution = [&](size_t j, const ThreadParams& p) {
    RowValues v(table.rows.size());
    const double coverage = init.threads[j].coverage;
    for (size_t i = 0; i < v.size(); ++i) {
      Vec3<double> s_j;
      double w_j;
      ThreadSums(p, *search_samples[i], j, &s_j, &w_j);
      v[i] = ConvertQuantity(s_j * (coverage * inv_q[i]),
                             Quantity::kCosineWeighted, table.quantity,
                             table.rows[i].wi.z);
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
    starts.push_back(CoverageToStick(*weave, x));
  }

  ClothFitResult result;
  std::vector<double> x = starts.front();
  result.report = SolveLeastSquares(lsq, starts, options.solver, &x);
  ReportWeighting(weighting, &result.report);
  result.params =
      FromVector(init, StickToCoverage(*weave, x), weave->shared_albedo);
  result.report.rows = static_cast<int>(table.rows.size());
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
