// The variables in which the Lafortune fits solve for a channel's lobes:
// the channel layout (rho_d, then Cx, Cy, Cz, N per lobe;
// models/lafortune.h) with each C_i = X_i LafortuneLobeReach(N) and
// X_i in [-1, 1], so that every lobe's peak |C|_inf^N stays within the
// energy normalisation (N + 2) / (2 pi) by construction, for any N in its
// search range, with box bounds only (the bounds-by-reparameterisation
// of Ceres' examples). The peak is also at most `peak_cap`: a texel's fit
// caps it at LafortunePeakCap of its samples, so that a lobe cannot peak
// far above everything measured where no sample looked. For
// fitting/lafortune_*.cc only.
#pragma once

#include <ceres/ceres.h>

#include <algorithm>
#include <vector>

#include "models/lafortune.h"

namespace clothfit {

// The channel layout x from the bounded variables y (any scalar type).
template <typename T>
void LobesFromBounded(const T* y, int lobes, double peak_cap, T* x) {
  x[0] = y[0];
  for (int k = 0; k < lobes; ++k) {
    const T* in = y + 1 + 4 * k;
    T* out = x + 1 + 4 * k;
    const T reach = LafortuneLobeReach(in[3], peak_cap);
    for (int i = 0; i < 3; ++i) out[i] = in[i] * reach;
    out[3] = in[3];
  }
}

// The bounded variables of x, each moved into its bounds (a start outside
// them starts on them).
inline std::vector<double> LobesToBounded(const double* x, int lobes,
                                          double peak_cap) {
  std::vector<double> y(LafortuneChannelSize(lobes));
  y[0] = std::clamp(x[0], kLafortuneDiffuse.fit_lo, kLafortuneDiffuse.fit_hi);
  for (int k = 0; k < lobes; ++k) {
    const double* in = x + 1 + 4 * k;
    double* out = y.data() + 1 + 4 * k;
    out[3] = std::clamp(in[3], kLafortuneN.fit_lo, kLafortuneN.fit_hi);
    const double reach = LafortuneLobeReach(out[3], peak_cap);
    for (int i = 0; i < 3; ++i) out[i] = std::clamp(in[i] / reach, -1.0, 1.0);
  }
  return y;
}

// A lobe's peak is at most this many times the largest value (rho, any
// channel) of a texel's rows: where the data show a peak, its samples are
// within a small factor of it; a lobe narrower than the sampling can
// otherwise put up to (N + 2) / (2 pi) = 32 between samples
// (tests/plausibility_test). Of the rows, not of the merged samples, so
// that merging repeated pairs leaves the cap unchanged.
inline constexpr double kLobePeakOverData = 10.0;
inline double LafortunePeakCap(double largest_row_value,
                               const std::vector<glm::dvec3>& values) {
  double largest = largest_row_value;
  for (const glm::dvec3& v : values) {
    largest = std::max({largest, v.x, v.y, v.z});
  }
  return largest > 0.0 ? kLobePeakOverData * largest : kInfinity;
}

// The box bounds of the bounded variables y.
inline void SetBoundedLobeBounds(int lobes, double* y, ceres::Problem* p) {
  p->SetParameterLowerBound(y, 0, kLafortuneDiffuse.fit_lo);
  p->SetParameterUpperBound(y, 0, kLafortuneDiffuse.fit_hi);
  for (int k = 0; k < lobes; ++k) {
    for (int i = 0; i < 3; ++i) {
      p->SetParameterLowerBound(y, 1 + 4 * k + i, -1.0);
      p->SetParameterUpperBound(y, 1 + 4 * k + i, 1.0);
    }
    p->SetParameterLowerBound(y, 4 + 4 * k, kLafortuneN.fit_lo);
    p->SetParameterUpperBound(y, 4 + 4 * k, kLafortuneN.fit_hi);
  }
}

// Whether every lobe of p lies within its reach (a rescaled model that
// the fits may keep).
inline bool LobesWithinReach(const LafortuneParams& p, double peak_cap) {
  for (const LafortuneLobe& lobe : p.lobes) {
    for (int c = 0; c < 3; ++c) {
      const double reach =
          LafortuneLobeReach(lobe.n[c], peak_cap) * (1.0 + 1e-12);
      if (std::abs(lobe.cx[c]) > reach || std::abs(lobe.cy[c]) > reach ||
          std::abs(lobe.cz[c]) > reach) {
        return false;
      }
    }
  }
  return true;
}

}  // namespace clothfit
