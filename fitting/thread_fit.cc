#include "fitting/thread_fit.h"

#include <algorithm>
#include <memory>

#include <ceres/ceres.h>

#include "fitting/least_squares.h"
#include "io/input_error.h"
#include "models/evaluate.h"

namespace clothfit {
namespace {

// residual_c = (s model_c - measured_c) sqrt(weight) / sigma_c, c <
// kChannels, with s = 1, or the free scale of data on an arbitrary scale
// (a second block).
template <int kChannels>
struct ThreadResidual {
  glm::dvec3 wi, wo, value, scale;
  Quantity quantity;

  template <typename T>
  bool operator()(const T* x, const T* s, T* residual) const {
    const Vec3<T> model = ThreadValue(ThreadParamsFromArray(x), Cast<T>(wi),
                                      Cast<T>(wo), quantity);
    for (int c = 0; c < kChannels; ++c) {
      residual[c] = ((s ? s[0] : T(1.0)) * model[c] - T(value[c])) * T(scale[c]);
    }
    return true;
  }
  template <typename T>
  bool operator()(const T* x, T* residual) const {
    return (*this)(x, static_cast<const T*>(nullptr), residual);
  }

  static ceres::CostFunction* Create(const TableRow& row, Quantity quantity,
                                     bool fit_scale) {
    auto* f = new ThreadResidual{row.wi, row.wo, row.value,
                                 std::sqrt(row.weight) / row.sigma, quantity};
    constexpr int P = ThreadParams::kSize;
    if (fit_scale) {
      return new ceres::AutoDiffCostFunction<ThreadResidual, kChannels, P, 1>(f);
    }
    return new ceres::AutoDiffCostFunction<ThreadResidual, kChannels, P>(f);
  }
};

std::vector<ParameterSpec> ThreadSpecs() {
  const char* const* names = ThreadParamNames();
  std::vector<ParameterSpec> specs(ThreadParams::kSize);
  const double lower[] = {1.01, 0.0, 0.2, 0.2, 0.0, 0.0, 0.0};
  const double upper[] = {3.0, 1.0, 90.0, 90.0, 1e3, 1e3, 1e3};
  for (int i = 0; i < ThreadParams::kSize; ++i) {
    specs[i] = ParameterSpec{names[i], lower[i], upper[i], true};
  }
  return specs;
}

// The model is linear in the albedo: model_c = surface + albedo_c volume_c,
// and, with a free scale s, s model_c = s surface + (s albedo_c) volume_c is
// linear in (s, s albedo_c). Solves the weighted non-negative least squares
// for those (projected Gauss-Seidel; 4 unknowns at most) and sets the
// albedo (and *scale, when not null).
void SolveLinearParameters(const MeasurementTable& table, ThreadParams* p,
                           double* scale) {
  ThreadParams no_albedo = *p, unit = *p;
  no_albedo.albedo = glm::dvec3(0.0);
  unit.albedo = glm::dvec3(1.0);
  // Unknowns: t_c = s albedo_c (c < channels), then s when free.
  const int channels = table.channels;
  const int m = channels + (scale ? 1 : 0);
  std::vector<double> ata(m * m, 0.0), atb(m, 0.0), basis(m);
  for (const TableRow& row : table.rows) {
    const glm::dvec3 surface =
        ThreadValue(no_albedo, row.wi, row.wo, table.quantity);
    const glm::dvec3 volume =
        ThreadValue(unit, row.wi, row.wo, table.quantity) - surface;
    for (int c = 0; c < channels; ++c) {
      const double w = row.weight / (row.sigma[c] * row.sigma[c]);
      std::fill(basis.begin(), basis.end(), 0.0);
      basis[c] = volume[c];
      double target = row.value[c];
      if (scale) {
        basis[channels] = surface[c];
      } else {
        target -= surface[c];
      }
      for (int a = 0; a < m; ++a) {
        atb[a] += w * basis[a] * target;
        for (int b = 0; b < m; ++b) ata[a * m + b] += w * basis[a] * basis[b];
      }
    }
  }
  std::vector<double> x(m, 0.0);
  if (scale) x[channels] = 1.0;
  for (int sweep = 0; sweep < 300; ++sweep) {
    for (int a = 0; a < m; ++a) {
      if (!(ata[a * m + a] > 0.0)) continue;
      double rhs = atb[a];
      for (int b = 0; b < m; ++b) {
        if (b != a) rhs -= ata[a * m + b] * x[b];
      }
      x[a] = std::clamp(rhs / ata[a * m + a], a == channels ? 1e-6 : 0.0, 1e6);
    }
  }
  const double s = scale ? x[channels] : 1.0;
  if (scale) *scale = s;
  for (int c = 0; c < 3; ++c) {
    p->albedo[c] = std::clamp(x[std::min(c, channels - 1)] / s, 0.0, 1e3);
  }
}

}  // namespace

std::vector<ThreadParams> DefaultThreadStarts() {
  std::vector<ThreadParams> starts;
  for (double gamma_s : {2.0, 6.0, 15.0}) {
    for (double kd : {0.1, 0.5}) {
      ThreadParams p;
      p.eta = 1.45;
      p.kd = kd;
      p.gamma_s_deg = gamma_s;
      p.gamma_v_deg = 2.0 * gamma_s;
      starts.push_back(p);
    }
  }
  return starts;
}

ThreadFitResult FitThread(const MeasurementTable& table,
                          const ThreadFitOptions& options) {
  if (table.quantity == Quantity::kTransmittance) {
    throw InputError("a thread model predicts brdf or cosine_weighted "
                     "values, not transmittance");
  }
  LeastSquaresProblem lsq;
  lsq.specs = ThreadSpecs();
  ApplyFreeFix(options.fix, options.free_only, &lsq.specs);
  if (table.channels == 1) {  // one channel: albedo_g, albedo_b follow r
    lsq.specs[5].free = lsq.specs[6].free = false;
  }
  lsq.block_sizes = {ThreadParams::kSize, 1};
  lsq.specs.push_back({"scale", 1e-6, 1e6, options.fit_scale});
  lsq.sigma_known = table.has_sigma;
  lsq.add_residuals = [&](const std::vector<double*>& blocks,
                          ceres::LossFunction* loss, ceres::Problem* problem) {
    for (const TableRow& row : table.rows) {
      ceres::CostFunction* cost =
          table.channels == 1
              ? ThreadResidual<1>::Create(row, table.quantity, options.fit_scale)
              : ThreadResidual<3>::Create(row, table.quantity, options.fit_scale);
      if (options.fit_scale) {
        problem->AddResidualBlock(cost, loss, blocks[0], blocks[1]);
      } else {
        problem->AddResidualBlock(cost, loss, blocks[0]);
      }
    }
  };
  lsq.predict = [&](const std::vector<double>& x, std::vector<double>* model,
                    std::vector<double>* measured) {
    const ThreadParams p = ThreadParamsFromArray(x.data());
    for (const TableRow& row : table.rows) {
      const glm::dvec3 m =
          x[ThreadParams::kSize] * ThreadValue(p, row.wi, row.wo, table.quantity);
      for (int c = 0; c < table.channels; ++c) {
        model->push_back(m[c]);
        measured->push_back(row.value[c]);
      }
    }
  };

  // Starts: the init, or the default grid with closed-form albedo, ranked.
  std::vector<std::vector<double>> starts;
  auto as_array = [](const ThreadParams& p) {
    std::vector<double> x(ThreadParams::kSize + 1, 1.0);  // scale = 1
    ToArray(p, x.data());
    return x;
  };
  if (options.init) {
    starts.push_back(as_array(*options.init));
  } else {
    std::vector<std::pair<double, std::vector<double>>> ranked;
    for (ThreadParams p :
         options.grid.empty() ? DefaultThreadStarts() : options.grid) {
      double scale = 1.0;
      SolveLinearParameters(table, &p, options.fit_scale ? &scale : nullptr);
      std::vector<double> x = as_array(p);
      x[ThreadParams::kSize] = scale;
      ranked.emplace_back(EvaluateCost(lsq, x), x);
    }
    std::stable_sort(ranked.begin(), ranked.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    const size_t n = std::clamp<size_t>(options.solve_starts, 1, ranked.size());
    for (size_t i = 0; i < n; ++i) starts.push_back(ranked[i].second);
  }

  ThreadFitResult result;
  std::vector<double> x = starts.front();
  result.report = SolveLeastSquares(lsq, starts, options.solver, &x);
  result.params = ThreadParamsFromArray(x.data());
  if (table.channels == 1) {  // one channel: one albedo
    result.params.albedo = glm::dvec3(result.params.albedo.x);
    for (ParameterReport& p : result.report.parameters) {
      if (p.name == "albedo_g" || p.name == "albedo_b") {
        p.value = result.params.albedo.x;
      }
    }
  }
  return result;
}

}  // namespace clothfit
