// The variables in which the Lafortune fits solve for a channel's lobes:
// the channel layout (rho_d, then Cx, Cy, Cz, N per lobe;
// models/lafortune.h) with each C_i = X_i LafortuneLobeReach(N) and
// X_i in [-1, 1], so that every lobe's peak |C|_inf^N stays within the
// energy normalisation (N + 2) / (2 pi) by construction, for any N in its
// search range, with box bounds only (the bounds-by-reparameterisation
// of Ceres' examples). For fitting/lafortune_*.cc only.
#pragma once

#include <ceres/ceres.h>

#include <algorithm>
#include <vector>

#include "models/lafortune.h"

namespace clothfit {

// The channel layout x from the bounded variables y (any scalar type).
template <typename T>
void LobesFromBounded(const T* y, int lobes, T* x) {
  x[0] = y[0];
  for (int k = 0; k < lobes; ++k) {
    const T* in = y + 1 + 4 * k;
    T* out = x + 1 + 4 * k;
    const T reach = LafortuneLobeReach(in[3]);
    for (int i = 0; i < 3; ++i) out[i] = in[i] * reach;
    out[3] = in[3];
  }
}

// The bounded variables of x, each moved into its bounds (a start outside
// them starts on them).
inline std::vector<double> LobesToBounded(const double* x, int lobes) {
  std::vector<double> y(LafortuneChannelSize(lobes));
  y[0] = std::clamp(x[0], kLafortuneDiffuse.fit_lo, kLafortuneDiffuse.fit_hi);
  for (int k = 0; k < lobes; ++k) {
    const double* in = x + 1 + 4 * k;
    double* out = y.data() + 1 + 4 * k;
    out[3] = std::clamp(in[3], kLafortuneN.fit_lo, kLafortuneN.fit_hi);
    const double reach = LafortuneLobeReach(out[3]);
    for (int i = 0; i < 3; ++i) out[i] = std::clamp(in[i] / reach, -1.0, 1.0);
  }
  return y;
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
inline bool LobesWithinReach(const LafortuneParams& p) {
  for (const LafortuneLobe& lobe : p.lobes) {
    for (int c = 0; c < 3; ++c) {
      const double reach = LafortuneLobeReach(lobe.n[c]) * (1.0 + 1e-12);
      if (std::abs(lobe.cx[c]) > reach || std::abs(lobe.cy[c]) > reach ||
          std::abs(lobe.cz[c]) > reach) {
        return false;
      }
    }
  }
  return true;
}

}  // namespace clothfit
