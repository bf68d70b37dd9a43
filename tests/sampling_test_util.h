// Goodness of fit of a direction sampler against its pdf, as Mitsuba's and
// pbrt's BSDF tests do it: the sphere in equal-area bins (kZ bands in
// z = cos(theta) times kPhi sectors in phi), the pdf integrated over each
// bin, and Pearson's chi-square of the sampled counts.
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include "models/math.h"

namespace clothfit {
namespace testing_util {

inline constexpr int kZBins = 16, kPhiBins = 32;

inline int SphereBin(const glm::dvec3& w) {
  const int iz =
      std::clamp(static_cast<int>((w.z + 1.0) * 0.5 * kZBins), 0, kZBins - 1);
  double phi = std::atan2(w.y, w.x);
  if (phi < 0.0) phi += 2.0 * kPi;
  const int ip = std::clamp(static_cast<int>(phi / (2.0 * kPi) * kPhiBins), 0,
                            kPhiBins - 1);
  return iz * kPhiBins + ip;
}

// The pdf integrated over every bin: the midpoint rule on an n x n grid in
// (z, phi) per bin (d omega = dz dphi). The bands at the poles are
// integrated in s with z = +-(1 - s^2) on a 4x finer grid, which takes out
// the 1 / sqrt(1 - z) of a density that concentrates at a pole (a thread
// cone about +z at normal view); the two bands at the horizon use a 4x
// finer grid in z and phi (a narrow lobe of a grazing view peaks there,
// its samples mirrored into the upper hemisphere).
inline std::vector<double> BinIntegrals(
    const std::function<double(const glm::dvec3&)>& pdf, int n) {
  std::vector<double> p(kZBins * kPhiBins, 0.0);
  const double band = 2.0 / kZBins;
  auto add_ring = [&](int bin_z, double z, double dz, int m) {
    const double r = std::sqrt(std::max(1.0 - z * z, 0.0));
    const double dphi = 2.0 * kPi / (kPhiBins * m);
    for (int k = 0; k < kPhiBins * m; ++k) {
      const double phi = (k + 0.5) * dphi;
      const glm::dvec3 w(r * std::cos(phi), r * std::sin(phi), z);
      p[bin_z * kPhiBins + k / m] += pdf(w) * dz * dphi;
    }
  };
  for (int b = 0; b < kZBins; ++b) {
    if (b == 0 || b == kZBins - 1) {
      const double sign = b == 0 ? -1.0 : 1.0;
      const int m = 4 * n;
      const double ds = std::sqrt(band) / m;
      for (int i = 0; i < m; ++i) {
        const double s = (i + 0.5) * ds;
        add_ring(b, sign * (1.0 - s * s), 2.0 * s * ds, n);
      }
      continue;
    }
    const int m = (b == kZBins / 2 - 1 || b == kZBins / 2) ? 4 * n : n;
    const double dz = band / m;
    for (int i = 0; i < m; ++i) {
      add_ring(b, -1.0 + b * band + (i + 0.5) * dz, dz, m);
    }
  }
  return p;
}

struct ChiSquare {
  double statistic = 0.0, critical = 0.0;
  int dof = 0;
  // Samples in the bins pooled for having fewer than 5 expected, when
  // those expected fewer than 5 in all.
  double stray = 0.0;
  bool Passes() const { return statistic < critical && stray < 20.0; }
};

// Pearson's statistic of `counts` against `samples` * `p` (bins with fewer
// than 5 expected pooled), against the critical value at significance
// 1e-4 (Wilson-Hilferty; z = 3.719).
inline ChiSquare Pearson(const std::vector<double>& counts,
                         const std::vector<double>& p, double samples) {
  ChiSquare out;
  double pooled_expected = 0.0, pooled_count = 0.0;
  int bins = 0;
  for (size_t b = 0; b < p.size(); ++b) {
    const double expected = p[b] * samples;
    if (expected < 5.0) {
      pooled_expected += expected;
      pooled_count += counts[b];
      continue;
    }
    out.statistic += (counts[b] - expected) * (counts[b] - expected) / expected;
    ++bins;
  }
  if (pooled_expected >= 5.0) {
    out.statistic += (pooled_count - pooled_expected) *
                     (pooled_count - pooled_expected) / pooled_expected;
    ++bins;
  } else {
    out.stray = pooled_count;
  }
  out.dof = bins - 1;
  const double k = out.dof, a = 2.0 / (9.0 * k);
  out.critical = k * std::pow(1.0 - a + 3.719 * std::sqrt(a), 3);
  return out;
}

}  // namespace testing_util
}  // namespace clothfit
