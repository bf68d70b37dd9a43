#include "fitting/holes_fit.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "fitting/least_squares.h"
#include "io/input_error.h"

namespace clothfit {
namespace {

// residual_c = (model_c - measured_c) sqrt(weight) / sigma_c, c < kChannels,
// with the model of the whole tile at the row's view direction.
template <int kChannels>
struct HolesResidual {
  glm::dvec3 wo, value, scale;
  const LevelTexels* texels;  // shared, read only
  HoleMethod method;

  template <typename T>
  bool operator()(const T* x, T* residual) const {
    const HolesParamsT<T> p = HolesParamsFromArray(x);
    const Vec3<T> model = HolesTransmittance(
        p, TileRatios(*texels, method, ViewOffset(p.thickness_texels, wo)));
    for (int c = 0; c < kChannels; ++c) {
      residual[c] = (model[c] - T(value[c])) * T(scale[c]);
    }
    return true;
  }

  static ceres::CostFunction* Create(const TableRow& row,
                                     const LevelTexels* texels,
                                     HoleMethod method) {
    return new ceres::AutoDiffCostFunction<HolesResidual, kChannels,
                                           HolesParams::kSize>(
        new HolesResidual{row.wo, row.value, std::sqrt(row.weight) / row.sigma,
                          texels, method});
  }
};

// thickness_texels: bounds that only limit the search (a fit that ends on
// one did not find h); the wall colour: its physical range.
constexpr double kMinThickness = 1e-3, kMaxThickness = 1e3;

std::vector<ParameterSpec> HolesSpecs(bool fit_wall_color) {
  const char* const* names = HolesParamNames();
  std::vector<ParameterSpec> specs;
  specs.push_back({names[0], kMinThickness, kMaxThickness, true, false});
  for (int c = 1; c < HolesParams::kSize; ++c) {
    specs.push_back({names[c], 0.0, 1.0, fit_wall_color, true});
  }
  return specs;
}

// Cost of h on the start grid, with each free wall-colour channel in closed
// form (the model is linear in it): c = <o, m - t> / <o, o> in [0, 1].
struct GridPoint {
  double cost = HUGE_VAL;
  HolesParams params;
};

GridPoint EvaluateStart(const MeasurementTable& table,
                        const LevelTexels& texels, HoleMethod method,
                        const std::vector<ParameterSpec>& specs,
                        HolesParams params) {
  const size_t n = table.rows.size();
  std::vector<HoleRatios> ratios(n);
  for (size_t i = 0; i < n; ++i) {
    ratios[i] = TileRatios(
        texels, method, ViewOffset(params.thickness_texels, table.rows[i].wo));
  }
  GridPoint point;
  point.cost = 0.0;
  for (int c = 0; c < table.channels; ++c) {
    if (specs[1 + c].free) {
      double num = 0.0, den = 0.0;
      for (size_t i = 0; i < n; ++i) {
        const TableRow& row = table.rows[i];
        const double w = row.weight / Sqr(row.sigma[c]);
        num += w * ratios[i].occluded * (row.value[c] - ratios[i].transparent);
        den += w * Sqr(ratios[i].occluded);
      }
      if (den > 0.0) params.wall_color[c] = std::clamp(num / den, 0.0, 1.0);
    }
    for (size_t i = 0; i < n; ++i) {
      const TableRow& row = table.rows[i];
      const double model =
          ratios[i].transparent + params.wall_color[c] * ratios[i].occluded;
      point.cost +=
          0.5 * row.weight * Sqr((model - row.value[c]) / row.sigma[c]);
    }
  }
  point.params = params;
  return point;
}

// The best point of a log grid over h (plus the init), and the best one at
// least a factor 2 away from it (another basin), as starts.
std::vector<std::vector<double>> SearchStarts(
    const MeasurementTable& table, const LevelTexels& texels, HoleMethod method,
    const std::vector<ParameterSpec>& specs, const HolesParams& init) {
  std::vector<GridPoint> points;
  if (specs[0].free) {
    for (double h = kMinThickness * 1.5; h < kMaxThickness;
         h *= std::pow(2.0, 0.25)) {
      HolesParams p = init;
      p.thickness_texels = h;
      points.push_back(EvaluateStart(table, texels, method, specs, p));
    }
  }
  points.push_back(EvaluateStart(table, texels, method, specs, init));
  std::sort(
      points.begin(), points.end(),
      [](const GridPoint& a, const GridPoint& b) { return a.cost < b.cost; });
  std::vector<std::vector<double>> starts;
  const double best_h = points.front().params.thickness_texels;
  for (const GridPoint& p : points) {
    const bool first = starts.empty();
    if (!first && std::abs(std::log(p.params.thickness_texels / best_h)) <
                      std::log(2.0)) {
      continue;
    }
    std::vector<double> x(HolesParams::kSize);
    ToArray(p.params, x.data());
    starts.push_back(x);
    if (starts.size() == 2) break;
  }
  return starts;
}

}  // namespace

HolesFitResult FitHoles(const MeasurementTable& table,
                        const HoleTexture& texture,
                        const HolesFitOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  if (table.quantity != Quantity::kTransmittance) {
    throw InputError(std::string("a holes model predicts transmittance; the "
                                 "table holds ") +
                     QuantityName(table.quantity));
  }
  const int top = texture.counts.levels() - 1;
  const int level = options.level < 0 ? top : options.level;
  if (level > top) {
    throw InputError("level " + std::to_string(level) +
                     " is out of range: the mask's pyramid has levels 0.." +
                     std::to_string(top));
  }
  if (options.method == HoleMethod::kExtension && texture.distances.empty()) {
    throw InputError("the extension needs the mask's run counts");
  }
  const HolesParams init = options.init ? *options.init : HolesParams();
  const std::string invalid = ValidateHolesParams(init);
  if (!invalid.empty()) throw InputError("initial parameters: " + invalid);
  const LevelTexels texels = GatherLevel(texture, level);

  LeastSquaresProblem lsq;
  lsq.specs = HolesSpecs(options.fit_wall_color);
  ApplyFreeFix(options.fix, options.free_only, &lsq.specs);
  if (table.channels == 1) {  // one channel: wall_color_g, _b follow r
    lsq.specs[2].free = lsq.specs[3].free = false;
  }
  lsq.block_sizes = {HolesParams::kSize};
  lsq.sigma_known = table.has_sigma;
  lsq.add_residuals = [&](const std::vector<double*>& blocks,
                          ceres::LossFunction* loss, ceres::Problem* problem) {
    for (const TableRow& row : table.rows) {
      problem->AddResidualBlock(
          table.channels == 1
              ? HolesResidual<1>::Create(row, &texels, options.method)
              : HolesResidual<3>::Create(row, &texels, options.method),
          loss, blocks[0]);
    }
  };
  lsq.predict = [&](const std::vector<double>& x, std::vector<double>* model,
                    std::vector<double>* measured,
                    std::vector<const TableRow*>* rows) {
    const HolesParams p = HolesParamsFromArray(x.data());
    for (const TableRow& row : table.rows) {
      const glm::dvec3 m = HolesTransmittance(
          p, TileRatios(texels, options.method,
                        ViewOffset(p.thickness_texels, row.wo)));
      for (int c = 0; c < table.channels; ++c) {
        model->push_back(m[c]);
        measured->push_back(row.value[c]);
        if (rows) rows->push_back(&row);
      }
    }
  };

  const std::vector<std::vector<double>> starts =
      SearchStarts(table, texels, options.method, lsq.specs, init);
  HolesFitResult result;
  std::vector<double> x = starts.front();
  result.report = SolveLeastSquares(lsq, starts, options.solver, &x);
  result.params = HolesParamsFromArray(x.data());
  if (table.channels == 1) {  // one channel: one wall colour
    result.params.wall_color =
        OneChannelRgb("wall_color", result.params.wall_color, &result.report);
  }
  result.report.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0)
          .count();
  return result;
}

}  // namespace clothfit
