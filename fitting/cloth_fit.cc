#include "fitting/cloth_fit.h"

#include <algorithm>
#include <memory>

#include <ceres/ceres.h>

#include "fitting/least_squares.h"
#include "io/input_error.h"
#include "models/evaluate.h"

namespace clothfit {
namespace {

// Parameter vector: per thread j, a block of the ThreadParams layout (7)
// followed by a weave block [coverage, offset_scale] (2). The thread's
// tangent offsets are offset_scale times the initial ones.
constexpr int kWeaveSize = 2;

// The weave shared by all residuals: directions and base offsets.
struct Weave {
  ClothParams layout;
};

template <typename T>
ClothParamsT<T> ClothFromBlocks(const Weave& weave, const T* const* blocks) {
  ClothParamsT<T> c;
  c.threads.resize(weave.layout.threads.size());
  for (size_t j = 0; j < c.threads.size(); ++j) {
    const ClothThread& base = weave.layout.threads[j];
    ClothThreadT<T>& th = c.threads[j];
    th.direction = base.direction;
    th.params = ThreadParamsFromArray(blocks[2 * j]);
    th.coverage = blocks[2 * j + 1][0];
    th.offsets_deg.resize(base.offsets_deg.size());
    for (size_t k = 0; k < base.offsets_deg.size(); ++k) {
      th.offsets_deg[k] = blocks[2 * j + 1][1] * T(base.offsets_deg[k]);
    }
  }
  return c;
}

// The tangent samples of one row, computed once when the directions and
// the tangent offsets are fixed (then only the thread BSDF needs Jets).
struct RowSamples {
  std::vector<std::vector<TangentSample<double>>> per_thread;
  int Count(size_t j) const { return static_cast<int>(per_thread[j].size()); }
  const TangentSample<double>& Get(size_t j, int k) const {
    return per_thread[j][k];
  }
};

RowSamples ComputeRowSamples(const ClothParams& layout, const TableRow& row) {
  RowSamples out;
  out.per_thread.resize(layout.threads.size());
  if (!(row.wi.z > 0.0 && row.wo.z > 0.0)) return out;  // reflection only
  for (size_t j = 0; j < layout.threads.size(); ++j) {
    for (double offset : layout.threads[j].offsets_deg) {
      out.per_thread[j].push_back(ComputeTangentSample(
          layout.threads[j].direction, offset, row.wi, row.wo));
    }
  }
  return out;
}

// residual_c = (model_c - measured_c) sqrt(weight) / sigma_c, c < kChannels.
// One overload per thread count (1 to 3): Ceres passes two blocks a thread.
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
      ClothParamsT<T> cloth;  // coverages and thread parameters only
      cloth.threads.resize(weave->layout.threads.size());
      for (size_t j = 0; j < cloth.threads.size(); ++j) {
        cloth.threads[j].params = ThreadParamsFromArray(blocks[2 * j]);
        cloth.threads[j].coverage = blocks[2 * j + 1][0];
      }
      model = FromCosineWeighted(ClothRhoFromSamples(cloth, *samples, wi.z),
                                 wi.z, quantity);
    } else {
      model = ClothValue(ClothFromBlocks(*weave, blocks), Cast<T>(wi),
                         Cast<T>(wo), quantity);
    }
    for (int c = 0; c < kChannels; ++c) {
      residual[c] = (model[c] - T(value[c])) * T(scale[c]);
    }
    return true;
  }
  template <typename T>
  bool operator()(const T* p0, const T* w0, T* r) const {
    const T* const b[] = {p0, w0};
    return Residual(b, r);
  }
  template <typename T>
  bool operator()(const T* p0, const T* w0, const T* p1, const T* w1,
                  T* r) const {
    const T* const b[] = {p0, w0, p1, w1};
    return Residual(b, r);
  }
  template <typename T>
  bool operator()(const T* p0, const T* w0, const T* p1, const T* w1,
                  const T* p2, const T* w2, T* r) const {
    const T* const b[] = {p0, w0, p1, w1, p2, w2};
    return Residual(b, r);
  }

  static ceres::CostFunction* Create(std::shared_ptr<const Weave> weave,
                                     const TableRow& row, Quantity quantity,
                                     std::shared_ptr<const RowSamples> samples) {
    constexpr int P = ThreadParams::kSize, W = kWeaveSize;
    auto* f = new ClothResidual{std::move(weave), row.wi, row.wo, row.value,
                                std::sqrt(row.weight) / row.sigma, quantity,
                                std::move(samples)};
    switch (f->weave->layout.threads.size()) {
      case 1:
        return new ceres::AutoDiffCostFunction<ClothResidual, kChannels, P, W>(f);
      case 2:
        return new ceres::AutoDiffCostFunction<ClothResidual, kChannels, P, W,
                                               P, W>(f);
      default:
        return new ceres::AutoDiffCostFunction<ClothResidual, kChannels, P, W,
                                               P, W, P, W>(f);
    }
  }
};

std::vector<ParameterSpec> ClothSpecs(const ClothParams& layout, int channels) {
  std::vector<ParameterSpec> specs;
  const char* const* names = ThreadParamNames();
  const double lower[] = {1.01, 0.0, 0.2, 0.2, 0.0, 0.0, 0.0};
  const double upper[] = {3.0, 1.0, 90.0, 90.0, 1e3, 1e3, 1e3};
  for (size_t j = 0; j < layout.threads.size(); ++j) {
    const std::string prefix = "threads[" + std::to_string(j) + "].";
    for (int i = 0; i < ThreadParams::kSize; ++i) {
      // eta is fixed by default: the data rarely separate it from kd/albedo.
      const bool free = i != 0 && !(channels == 1 && i >= 5);
      specs.push_back({prefix + names[i], lower[i], upper[i], free});
    }
    double largest = 0.0;
    for (double o : layout.threads[j].offsets_deg) {
      largest = std::max(largest, std::abs(o));
    }
    specs.push_back({prefix + "coverage", 0.0, 1.0, false});
    specs.push_back({prefix + "offset_scale", 0.0,
                     largest > 0.0 ? 90.0 / largest : 1.0, false});
  }
  return specs;
}

std::vector<double> ToVector(const ClothParams& c) {
  std::vector<double> x;
  for (const ClothThread& th : c.threads) {
    double p[ThreadParams::kSize];
    ToArray(th.params, p);
    x.insert(x.end(), p, p + ThreadParams::kSize);
    x.push_back(th.coverage);
    x.push_back(1.0);  // offset_scale relative to the layout
  }
  return x;
}

ClothParams FromVector(const Weave& weave, const std::vector<double>& x) {
  std::vector<const double*> blocks;
  for (size_t j = 0; j < weave.layout.threads.size(); ++j) {
    blocks.push_back(x.data() + j * (ThreadParams::kSize + kWeaveSize));
    blocks.push_back(blocks.back() + ThreadParams::kSize);
  }
  ClothParams c = ClothFromBlocks<double>(weave, blocks.data());
  for (size_t j = 0; j < c.threads.size(); ++j) {
    c.threads[j].curve = weave.layout.threads[j].curve;
  }
  return c;
}

// The model is linear in the albedos: per channel, the least-squares albedo
// of each thread, with negative ones clamped to zero (2-3 unknowns).
void SolveAlbedos(const MeasurementTable& table, ClothParams* c) {
  const size_t n = c->threads.size();
  ClothParams base = *c;
  for (ClothThread& th : base.threads) th.params.albedo = glm::dvec3(0.0);
  std::vector<ClothParams> unit(n, base);
  for (size_t j = 0; j < n; ++j) unit[j].threads[j].params.albedo = glm::dvec3(1.0);
  for (int channel = 0; channel < 3; ++channel) {
    std::vector<double> ata(n * n, 0.0), atb(n, 0.0);
    for (const TableRow& row : table.rows) {
      const double w = row.weight / (row.sigma[channel] * row.sigma[channel]);
      const double s = ClothValue(base, row.wi, row.wo, table.quantity)[channel];
      std::vector<double> a(n);
      for (size_t j = 0; j < n; ++j) {
        a[j] = ClothValue(unit[j], row.wi, row.wo, table.quantity)[channel] - s;
      }
      for (size_t i = 0; i < n; ++i) {
        atb[i] += w * a[i] * (row.value[channel] - s);
        for (size_t j = 0; j < n; ++j) ata[i * n + j] += w * a[i] * a[j];
      }
    }
    // Jacobi-preconditioned projected Gauss-Seidel: tiny, non-negative.
    std::vector<double> albedo(n, 0.0);
    for (int sweep = 0; sweep < 200; ++sweep) {
      for (size_t i = 0; i < n; ++i) {
        if (ata[i * n + i] <= 0.0) continue;
        double r = atb[i];
        for (size_t j = 0; j < n; ++j) {
          if (j != i) r -= ata[i * n + j] * albedo[j];
        }
        albedo[i] = std::clamp(r / ata[i * n + i], 0.0, 1e3);
      }
    }
    for (size_t j = 0; j < n; ++j) c->threads[j].params.albedo[channel] = albedo[j];
  }
}

bool NameEndsWith(const std::string& name, const std::string& suffix) {
  return name.size() >= suffix.size() &&
         name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0;
}

}  // namespace

std::vector<std::string> ClothParameterNames(const ClothParams& layout) {
  std::vector<std::string> names;
  for (const ParameterSpec& s : ClothSpecs(layout, 3)) names.push_back(s.name);
  return names;
}

std::vector<double> ClothParameterValues(const ClothParams& c,
                                         const ClothParams& layout) {
  std::vector<double> x = ToVector(c);
  for (size_t j = 0; j < c.threads.size() && j < layout.threads.size(); ++j) {
    double mine = 0.0, theirs = 0.0;
    for (double o : c.threads[j].offsets_deg) mine = std::max(mine, std::abs(o));
    for (double o : layout.threads[j].offsets_deg) {
      theirs = std::max(theirs, std::abs(o));
    }
    x[j * (ThreadParams::kSize + kWeaveSize) + ThreadParams::kSize + 1] =
        theirs > 0.0 ? mine / theirs : 1.0;
  }
  return x;
}

ClothFitResult FitCloth(const MeasurementTable& table, const ClothParams& init,
                        const ClothFitOptions& options) {
  if (table.quantity == Quantity::kTransmittance) {
    throw InputError("a cloth model predicts brdf or cosine_weighted values, "
                     "not transmittance");
  }
  if (init.threads.empty() || init.threads.size() > 3) {
    throw InputError("cloth fit: the initial parameters need 1 to 3 threads, got " +
                     std::to_string(init.threads.size()));
  }
  auto weave = std::make_shared<Weave>();
  weave->layout = init;
  LeastSquaresProblem lsq;
  lsq.specs = ClothSpecs(init, table.channels);
  ApplyFreeFix(options.fix, options.free_only, &lsq.specs);
  for (size_t j = 0; j < init.threads.size(); ++j) {
    lsq.block_sizes.push_back(ThreadParams::kSize);
    lsq.block_sizes.push_back(kWeaveSize);
  }
  lsq.sigma_known = table.has_sigma;
  // With every offset_scale fixed the tangent samples never change: compute
  // them once for all solves.
  bool offsets_fixed = true;
  for (const ParameterSpec& spec : lsq.specs) {
    if (spec.free && NameEndsWith(spec.name, ".offset_scale")) {
      offsets_fixed = false;
    }
  }
  std::vector<std::shared_ptr<const RowSamples>> row_samples(table.rows.size());
  if (offsets_fixed) {
    for (size_t i = 0; i < table.rows.size(); ++i) {
      row_samples[i] = std::make_shared<const RowSamples>(
          ComputeRowSamples(init, table.rows[i]));
    }
  }
  lsq.add_residuals = [&](const std::vector<double*>& blocks,
                          ceres::LossFunction* loss, ceres::Problem* problem) {
    for (size_t i = 0; i < table.rows.size(); ++i) {
      const TableRow& row = table.rows[i];
      ceres::CostFunction* cost =
          table.channels == 1
              ? ClothResidual<1>::Create(weave, row, table.quantity,
                                         row_samples[i])
              : ClothResidual<3>::Create(weave, row, table.quantity,
                                         row_samples[i]);
      problem->AddResidualBlock(cost, loss, blocks);
    }
  };
  lsq.predict = [&](const std::vector<double>& x, std::vector<double>* model,
                    std::vector<double>* measured) {
    const ClothParams c = FromVector(*weave, x);
    for (const TableRow& row : table.rows) {
      const glm::dvec3 m = ClothValue(c, row.wi, row.wo, table.quantity);
      for (int ch = 0; ch < table.channels; ++ch) {
        model->push_back(m[ch]);
        measured->push_back(row.value[ch]);
      }
    }
  };

  // Starts: the init, and (multi-start) variations of its widths and kd,
  // each with closed-form albedos; ranked by cost.
  std::vector<ClothParams> candidates = {init};
  if (options.multi_start) {
    for (double gamma_factor : {1.0, 0.5, 2.0}) {
      for (double kd : {-1.0, 0.1, 0.6}) {
        ClothParams c = init;
        for (size_t j = 0; j < c.threads.size(); ++j) {
          ThreadParams& p = c.threads[j].params;
          const std::string prefix = "threads[" + std::to_string(j) + "].";
          auto is_free = [&](const std::string& name) {
            for (const ParameterSpec& s : lsq.specs) {
              if (s.name == prefix + name) return s.free;
            }
            return false;
          };
          if (is_free("gamma_s_deg")) {
            p.gamma_s_deg = std::clamp(p.gamma_s_deg * gamma_factor, 0.2, 90.0);
          }
          if (is_free("gamma_v_deg")) {
            p.gamma_v_deg = std::clamp(p.gamma_v_deg * gamma_factor, 0.2, 90.0);
          }
          if (kd >= 0.0 && is_free("kd")) p.kd = kd;
        }
        bool albedo_free = false;
        for (const ParameterSpec& s : lsq.specs) {
          albedo_free = albedo_free || (s.free && s.name.find("albedo") != std::string::npos);
        }
        if (albedo_free) SolveAlbedos(table, &c);
        candidates.push_back(c);
      }
    }
  }
  std::vector<std::pair<double, std::vector<double>>> ranked;
  for (const ClothParams& c : candidates) {
    const std::vector<double> x = ToVector(c);
    ranked.emplace_back(EvaluateCost(lsq, x), x);
  }
  std::stable_sort(ranked.begin(), ranked.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  const size_t n = std::clamp<size_t>(options.solve_starts, 1, ranked.size());
  std::vector<std::vector<double>> starts;
  for (size_t i = 0; i < n; ++i) starts.push_back(ranked[i].second);

  ClothFitResult result;
  std::vector<double> x = starts.front();
  result.report = SolveLeastSquares(lsq, starts, options.solver, &x);
  result.params = FromVector(*weave, x);
  if (table.channels == 1) {
    for (ClothThread& th : result.params.threads) {
      th.params.albedo = glm::dvec3(th.params.albedo.x);
    }
  }
  return result;
}

}  // namespace clothfit
