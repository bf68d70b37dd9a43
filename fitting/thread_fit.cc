#include "fitting/thread_fit.h"

#include <algorithm>
#include <memory>

#include <ceres/ceres.h>

#include "fitting/least_squares.h"
#include "io/input_error.h"
#include "models/evaluate.h"

namespace clothfit {
namespace {

// residual_c = (model_c - measured_c) sqrt(weight) / sigma_c, c < kChannels.
template <int kChannels>
struct ThreadResidual {
  glm::dvec3 wi, wo, value, scale;
  Quantity quantity;

  template <typename T>
  bool operator()(const T* x, T* residual) const {
    const Vec3<T> model = ThreadValue(ThreadParamsFromArray(x), Cast<T>(wi),
                                      Cast<T>(wo), quantity);
    for (int c = 0; c < kChannels; ++c) {
      residual[c] = (model[c] - T(value[c])) * T(scale[c]);
    }
    return true;
  }

  static ceres::CostFunction* Create(const TableRow& row, Quantity quantity) {
    return new ceres::AutoDiffCostFunction<ThreadResidual, kChannels,
                                           ThreadParams::kSize>(
        new ThreadResidual{row.wi, row.wo, row.value,
                           std::sqrt(row.weight) / row.sigma, quantity});
  }
};

std::vector<ParameterSpec> ThreadSpecs(int channels) {
  const char* const* names = ThreadParamNames();
  std::vector<ParameterSpec> specs(ThreadParams::kSize);
  const double lower[] = {1.01, 0.0, 0.2, 0.2, 0.0, 0.0, 0.0};
  const double upper[] = {3.0, 1.0, 90.0, 90.0, 1e3, 1e3, 1e3};
  for (int i = 0; i < ThreadParams::kSize; ++i) {
    specs[i] = ParameterSpec{names[i], lower[i], upper[i], true};
  }
  if (channels == 1) specs[5].free = specs[6].free = false;  // tied to r
  return specs;
}

// The model is linear in the albedo: model = surface + albedo_c * volume_c.
// Sets each channel's albedo to its non-negative least-squares value.
void SolveAlbedo(const MeasurementTable& table, ThreadParams* p) {
  ThreadParams no_albedo = *p, unit = *p;
  no_albedo.albedo = glm::dvec3(0.0);
  unit.albedo = glm::dvec3(1.0);
  glm::dvec3 num(0.0), den(0.0);
  for (const TableRow& row : table.rows) {
    const glm::dvec3 w = row.weight / (row.sigma * row.sigma);
    const glm::dvec3 s = ThreadValue(no_albedo, row.wi, row.wo, table.quantity);
    const glm::dvec3 v =
        ThreadValue(unit, row.wi, row.wo, table.quantity) - s;
    num += w * v * (row.value - s);
    den += w * v * v;
  }
  for (int c = 0; c < 3; ++c) {
    p->albedo[c] = den[c] > 0.0 ? std::clamp(num[c] / den[c], 0.0, 1e3) : 0.0;
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
  lsq.specs = ThreadSpecs(table.channels);
  ApplyFreeFix(options.fix, options.free_only, &lsq.specs);
  lsq.block_sizes = {ThreadParams::kSize};
  lsq.sigma_known = table.has_sigma;
  lsq.add_residuals = [&](const std::vector<double*>& blocks,
                          ceres::LossFunction* loss, ceres::Problem* problem) {
    for (const TableRow& row : table.rows) {
      ceres::CostFunction* cost =
          table.channels == 1
              ? ThreadResidual<1>::Create(row, table.quantity)
              : ThreadResidual<3>::Create(row, table.quantity);
      problem->AddResidualBlock(cost, loss, blocks[0]);
    }
  };
  lsq.predict = [&](const std::vector<double>& x, std::vector<double>* model,
                    std::vector<double>* measured) {
    const ThreadParams p = ThreadParamsFromArray(x.data());
    for (const TableRow& row : table.rows) {
      const glm::dvec3 m = ThreadValue(p, row.wi, row.wo, table.quantity);
      for (int c = 0; c < table.channels; ++c) {
        model->push_back(m[c]);
        measured->push_back(row.value[c]);
      }
    }
  };

  // Starts: the init, or the default grid with closed-form albedo, ranked.
  std::vector<std::vector<double>> starts;
  auto as_array = [](const ThreadParams& p) {
    std::vector<double> x(ThreadParams::kSize);
    ToArray(p, x.data());
    return x;
  };
  if (options.init) {
    starts.push_back(as_array(*options.init));
  } else {
    std::vector<std::pair<double, std::vector<double>>> ranked;
    for (ThreadParams p :
         options.grid.empty() ? DefaultThreadStarts() : options.grid) {
      SolveAlbedo(table, &p);
      const std::vector<double> x = as_array(p);
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
