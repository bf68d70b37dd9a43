#include "fitting/thread_fit.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <chrono>
#include <memory>

#include "fitting/least_squares.h"
#include "fitting/start_search.h"
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
      residual[c] =
          ((s ? s[0] : T(1.0)) * model[c] - T(value[c])) * T(scale[c]);
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
      return new ceres::AutoDiffCostFunction<ThreadResidual, kChannels, P, 1>(
          f);
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
    // kd and the albedo are bounded by their physical range (i = 1, 4..6).
    specs[i] =
        ParameterSpec{names[i], lower[i], upper[i], true, i == 1 || i >= 4};
  }
  return specs;
}

}  // namespace

ThreadFitResult FitThread(const MeasurementTable& table,
                          const ThreadFitOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();  // search + solves
  if (table.quantity == Quantity::kTransmittance) {
    throw InputError(
        "a thread model predicts brdf or cosine_weighted "
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
          table.channels == 1 ? ThreadResidual<1>::Create(row, table.quantity,
                                                          options.fit_scale)
                              : ThreadResidual<3>::Create(row, table.quantity,
                                                          options.fit_scale);
      if (options.fit_scale) {
        problem->AddResidualBlock(cost, loss, blocks[0], blocks[1]);
      } else {
        problem->AddResidualBlock(cost, loss, blocks[0]);
      }
    }
  };
  lsq.predict = [&](const std::vector<double>& x, std::vector<double>* model,
                    std::vector<double>* measured,
                    std::vector<const TableRow*>* rows) {
    const ThreadParams p = ThreadParamsFromArray(x.data());
    for (const TableRow& row : table.rows) {
      const glm::dvec3 m = x[ThreadParams::kSize] *
                           ThreadValue(p, row.wi, row.wo, table.quantity);
      for (int c = 0; c < table.channels; ++c) {
        model->push_back(m[c]);
        measured->push_back(row.value[c]);
        if (rows) rows->push_back(&row);
      }
    }
  };

  // Starts: a grid search over the widths (and eta) with the linear
  // parameters (albedo, kd, scale) solved in closed form; the init's values
  // join the grid, fixed entries keep them (fitting/start_search.h).
  StartSearchProblem search;
  search.table = &table;
  search.init = {options.init ? *options.init : ThreadParams()};
  search.contribution = [&](size_t, const ThreadParams& p) {
    RowValues v(table.rows.size());
    for (size_t i = 0; i < v.size(); ++i) {
      v[i] = ThreadValue(p, table.rows[i].wi, table.rows[i].wo, table.quantity);
    }
    return v;
  };
  search.kd_free = {lsq.specs[1].free};
  search.gamma_s_free = {lsq.specs[2].free};
  search.gamma_v_free = {lsq.specs[3].free};
  search.albedo_free = {lsq.specs[4].free || lsq.specs[5].free ||
                        lsq.specs[6].free};
  search.fit_scale = options.fit_scale;
  std::vector<std::vector<double>> starts;
  for (const StartPoint& point :
       SearchStarts(search, std::max(1, options.solve_starts))) {
    std::vector<double> x(ThreadParams::kSize + 1);
    ToArray(point.threads[0], x.data());
    x[ThreadParams::kSize] = point.scale;
    starts.push_back(x);
  }

  ThreadFitResult result;
  std::vector<double> x = starts.front();
  result.report = SolveLeastSquares(lsq, starts, options.solver, &x);
  result.params = ThreadParamsFromArray(x.data());
  if (table.channels == 1) {  // one channel: one albedo
    result.params.albedo =
        OneChannelRgb("albedo", result.params.albedo, &result.report);
  }
  result.report.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0)
          .count();
  return result;
}

}  // namespace clothfit
