#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "fitting/ceres_linear_solver_internal.h"
#include "fitting/lafortune_bounds_internal.h"
#include "fitting/lafortune_joint_internal.h"
#include "fitting/lafortune_lobes_internal.h"
#include "fitting/model_residual_internal.h"
#include "fitting/residual_weight.h"
#include "models/lafortune.h"

namespace clothfit {
namespace {

// All residuals of one channel of one texel, T(v_i) f1(l_i, v_i) - y_i
// weighted (fitting/residual_weight.h), with T fixed (eq. 3 with the
// lookup table of the last pass). Per sample the fixed terms are
// precomputed - the products l_x v_x, l_y v_y, l_z v_z and the factor
// T(v) max(l_z, 0) - so that the solver's many evaluations do only the
// lobes (LobeSum, models/lafortune.h).
using ChannelTerms = LafortuneSampleTerms;

// Sample i's terms in channel `channel` with T fixed at lut (per view).
ChannelTerms ChannelTermsOf(const TexelSamples& s,
                            const std::vector<double>& lut, int channel,
                            size_t i) {
  const glm::dvec3& l = s.l[i];
  const glm::dvec3& v = s.v[i];
  return {l.x * v.x,           l.y * v.y,
          l.z * v.z,           lut[s.view[i]] * Foreshortening(l),
          s.value[i][channel], std::sqrt(s.weight[i][channel])};
}

// The residual of one sample's terms at the channel layout x.
template <int kLobes, typename T>
T ChannelResidualOf(const T* x, const ChannelTerms& s) {
  return WeightedResidual(LobeSum(x, kLobes, s.xx, s.yy, s.zz) * s.factor,
                          s.measured, s.scale);
}

// The variables are the bounded ones (fitting/lafortune_bounds_internal.h).
template <int kLobes>
struct ChannelResidual {
  const std::vector<ChannelTerms> terms;
  const double peak_cap;

  template <typename T>
  bool operator()(const T* y, T* residual) const {
    T x[1 + 4 * kLobes];
    LobesFromBounded(y, kLobes, peak_cap, x);
    for (size_t i = 0; i < terms.size(); ++i) {
      residual[i] = ChannelResidualOf<kLobes>(x, terms[i]);
    }
    return true;
  }

  static ceres::CostFunction* Create(std::vector<ChannelTerms> terms,
                                     double peak_cap) {
    const int n = static_cast<int>(terms.size());
    return new ceres::AutoDiffCostFunction<ChannelResidual, ceres::DYNAMIC,
                                           1 + 4 * kLobes>(
        new ChannelResidual{std::move(terms), peak_cap}, n);
  }
};

std::vector<ChannelTerms> MakeChannelTerms(const TexelSamples& s,
                                           const std::vector<double>& lut,
                                           int channel) {
  std::vector<ChannelTerms> terms(s.size());
  for (size_t i = 0; i < s.size(); ++i) {
    terms[i] = ChannelTermsOf(s, lut, channel, i);
  }
  return terms;
}

// The residuals of samples [begin, end) of one channel, as ChannelResidual
// but with the terms computed from the samples on each evaluation: for
// more than max_one_block_samples samples (LafortuneFitOptions), added as
// compressed chunks (fitting/compressed_rows.cc), so that neither the terms of
// every sample nor the solver's Jacobian of every sample is held. The samples
// and the lookup table `lut` outlive the solve.
template <int kLobes>
struct ChannelChunkResidual {
  const TexelSamples* samples;
  const std::vector<double>* lut;
  const int channel;
  const size_t begin, end;
  const double peak_cap;

  template <typename T>
  bool operator()(const T* y, T* residual) const {
    T x[1 + 4 * kLobes];
    LobesFromBounded(y, kLobes, peak_cap, x);
    for (size_t i = begin; i < end; ++i) {
      residual[i - begin] = ChannelResidualOf<kLobes>(
          x, ChannelTermsOf(*samples, *lut, channel, i));
    }
    return true;
  }

  static ceres::CostFunction* Create(const TexelSamples& samples,
                                     const std::vector<double>& lut,
                                     int channel, size_t begin, size_t end,
                                     double peak_cap) {
    return new ceres::AutoDiffCostFunction<ChannelChunkResidual, ceres::DYNAMIC,
                                           1 + 4 * kLobes>(
        new ChannelChunkResidual{&samples, &lut, channel, begin, end, peak_cap},
        static_cast<int>(end - begin));
  }
};

// The lobe count is a template argument: the solver's inner loop unrolls.
ceres::CostFunction* MakeChannelCost(int lobes, std::vector<ChannelTerms> terms,
                                     double peak_cap) {
  switch (lobes) {
    case 0:
      return ChannelResidual<0>::Create(std::move(terms), peak_cap);
    case 1:
      return ChannelResidual<1>::Create(std::move(terms), peak_cap);
    case 2:
      return ChannelResidual<2>::Create(std::move(terms), peak_cap);
    default:
      return ChannelResidual<3>::Create(std::move(terms), peak_cap);
  }
}

ceres::CostFunction* MakeChannelChunkCost(int lobes,
                                          const TexelSamples& samples,
                                          const std::vector<double>& lut,
                                          int channel, size_t begin, size_t end,
                                          double peak_cap) {
  switch (lobes) {
    case 0:
      return ChannelChunkResidual<0>::Create(samples, lut, channel, begin, end,
                                             peak_cap);
    case 1:
      return ChannelChunkResidual<1>::Create(samples, lut, channel, begin, end,
                                             peak_cap);
    case 2:
      return ChannelChunkResidual<2>::Create(samples, lut, channel, begin, end,
                                             peak_cap);
    default:
      return ChannelChunkResidual<3>::Create(samples, lut, channel, begin, end,
                                             peak_cap);
  }
}

// One Levenberg-Marquardt pass on one channel (x in the channel layout,
// solved in the bounded variables: a start outside the bounds starts on
// them; far_start: from the paper's or a given start, not next to the
// solution); returns iterations.
int SolveChannel(const TexelSamples& samples, const std::vector<double>& lut,
                 int channel, int lobes, const LafortuneFitOptions& fit,
                 double peak_cap, bool far_start, double* x) {
  std::vector<double> y = LobesToBounded(x, lobes, peak_cap);
  LobesFromBounded(y.data(), lobes, peak_cap, x);
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
  if (samples.size() <= fit.max_one_block_samples) {
    problem.AddResidualBlock(
        MakeChannelCost(lobes, MakeChannelTerms(samples, lut, channel),
                        peak_cap),
        nullptr, y.data());
  } else {
    for (size_t begin = 0; begin < samples.size(); begin += kChunkRows) {
      const size_t end = std::min(samples.size(), begin + kChunkRows);
      AddCompressedRows(MakeChannelChunkCost(lobes, samples, lut, channel,
                                             begin, end, peak_cap),
                        {y.data()}, &problem);
    }
  }
  SetBoundedLobeBounds(lobes, y.data(), &problem);
  ceres::Solver::Options options;
  SetCeresLinearSolver(fit.linear_solver, &options);
  options.max_num_iterations = fit.max_iterations;
  options.function_tolerance = fit.function_tolerance;
  options.num_threads = 1;
  // From a far start (the first pass) Ceres' projected line search
  // steadies the steps: without it CUReT tables' held-out errors rose by
  // up to 26 % (polyester zoomed), median 0.102 -> 0.106. Next to the
  // solution it only costs Jacobians (fitting/ceres_linear_solver_internal.h).
  if (!far_start) SkipProjectedLineSearch(&options);
  options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  LobesFromBounded(y.data(), lobes, peak_cap, x);
  return static_cast<int>(summary.iterations.size());
}

}  // namespace

// Fits all three channels' lobes with the given lookup table. The first
// pass (from a far start) runs Ceres' projected line search and, with
// options.warm_channels, channels 1 and 2 start from channel 0's solution
// scaled to their data (diffuse by the ratio s of the channel sums, each
// lobe's C by s^(1/N), so its value scales by s): the channels of a texel
// share their shape, and a start next to the solution saves iterations.
// Returns the solver's iterations.
int FitLobes(const TexelSamples& samples, const std::vector<glm::dvec3>& t,
             const LafortuneFitOptions& options, bool first_pass,
             double peak_cap, LafortuneParams* p) {
  const bool warm_channels = first_pass && options.warm_channels;
  int iterations = 0;
  const int lobes = static_cast<int>(p->lobes.size());
  std::vector<double> x(LafortuneChannelSize(lobes));
  glm::dvec3 sum(0.0);
  for (const glm::dvec3& y : samples.value) sum += y;
  for (int c = 0; c < 3; ++c) {
    LafortuneChannelToArray(*p, c, x.data());
    if (warm_channels && c > 0 && sum[0] > 0.0 && sum[c] > 0.0) {
      const double scale = sum[c] / sum[0];
      LafortuneChannelToArray(*p, 0, x.data());
      x[0] *= scale;
      for (int k = 0; k < lobes; ++k) {
        for (int i = 1; i <= 3; ++i) {
          x[4 * k + i] *= std::pow(scale, 1.0 / x[4 * k + 4]);
        }
      }
    }
    std::vector<double> lut(t.size());
    for (size_t k = 0; k < t.size(); ++k) lut[k] = t[k][c];
    iterations += SolveChannel(samples, lut, c, lobes, options, peak_cap,
                               first_pass, x.data());
    LafortuneChannelFromArray(x.data(), c, p);
  }
  return iterations;
}

}  // namespace clothfit
