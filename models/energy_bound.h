// An energy bound for models that reflect more than they receive toward
// grazing (clothfit's; not in Sadeghi et al. 2013). With the light-side and
// view-side directional albedos of a BRDF f,
//
//   A_L(wi) = integral of f(wi, wo) wo.z dw_o,
//   A_V(wo) = integral of f(wi, wo) wi.z dw_i,
//
// the bounded model is
//
//   f'(wi, wo) = f(wi, wo) h(wi.z) h(wo.z) / max(1, A_L(wi), A_V(wo)),
//
// with the horizon fade h(c) = min(1, c / cos 87 deg). Then the integral of
// f' wo.z over wo is at most A_L(wi) / max(1, A_L(wi)) <= 1, and likewise on
// the view side: f' conserves energy for light from every direction and
// toward every direction (white furnace, models/albedo.h). Where both
// albedos are at most 1 and both directions are within 87 degrees of the
// normal, f' = f: a model that conserves energy is unchanged there, and a
// reciprocal f (A_L = A_V) stays reciprocal.
//
// Sadeghi et al.'s thread (eq. 2-4) and cloth (eq. 5-13) need it: a thread
// alone exceeds 1 from about 60 degrees (its view side along the axis: 1.5
// at 80, 2.6 at 87 and over 5 at 89.9 degrees for the satin's thread, a
// peak a quadrature resolves only with hundreds of rings), and the cloth's
// light side grows as 1 / cos(theta_i), since its normalisation Q (eq.
// 12-13) keeps the threads' projected area as the light goes to grazing
// (the linen weave: 1.1 at 80, 3.7 at 87 degrees). The fade
// takes the last 3 degrees, where no gonioreflectometer measures, out of
// the tables: there c A(c) grows with c (the albedos grow slower than
// 1 / c), so the fade and the tables' values at 87 degrees bound them.
//
// The albedos are tabulated against c = cos(theta) at kEnergyBoundNodes
// nodes from 0 to 1, evenly spaced in sqrt(c) (dense toward grazing), each
// the largest over azimuth (so the bound depends on the polar angles only)
// widened by kEnergyBoundMargin; nodes beyond 87 degrees hold the values
// at 87. Between nodes the tables are interpolated linearly; the margin
// covers the quadrature's error and the curvature (the tests check the
// bounded presets with a dense furnace). The light table holds c A_L,
// which stays finite at grazing; in terms of rho = f wi.z,
//
//   rho'(wi, wo) = rho(wi, wo) h(c_i) h(c_o) c_i / max(c_i, L(c_i),
//                                                      c_i V(c_o)).
#pragma once

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "models/albedo.h"
#include "models/math.h"

namespace clothfit {

inline constexpr int kEnergyBoundNodes = 17;
// The tables' headroom over the albedos they were computed from (the
// quadrature's error at peaked lobes; the dense check of the tests).
inline constexpr double kEnergyBoundMargin = 1.05;
// The horizon fade's cosine, cos 87 degrees: below it the model fades
// linearly to 0 at the horizon, and the tables hold its values there.
inline constexpr double kEnergyBoundFadeCos = 0.05233595624294383;

struct EnergyBound {
  std::vector<double> light;  // c_k A_L at c_k = EnergyBoundNode(k, n)
  std::vector<double> view;   // A_V at c_k
};

// "" when a bound's tables are usable: equal sizes of at least 2, finite,
// light >= 0 and view >= 0.
inline const char* ValidateEnergyBound(const EnergyBound& b) {
  if (b.light.size() < 2 || b.light.size() != b.view.size()) {
    return "light and view must have the same number of entries (at least 2)";
  }
  for (size_t k = 0; k < b.light.size(); ++k) {
    if (!(b.light[k] >= 0.0 && b.light[k] < HUGE_VAL && b.view[k] >= 0.0 &&
          b.view[k] < HUGE_VAL)) {
      return "entries must be finite and >= 0";
    }
  }
  return "";
}

// The node c_k = (k / (n - 1))^2 of n: dense toward grazing, where the
// albedos change fastest.
inline double EnergyBoundNode(int k, int n) {
  const double x = static_cast<double>(k) / (n - 1);
  return x * x;
}

namespace energy_bound_internal {

inline double ScalarOf(double x) { return x; }
inline double ScalarOf(float x) { return x; }
// A Ceres Jet: its value (the tables are constants; only the position
// between nodes carries a derivative).
template <typename J>
double ScalarOf(const J& x) {
  return ScalarOf(x.a);
}

// The table linearly interpolated at c (clamped to [0, 1]) between the
// nodes c_k = (k / (n - 1))^2.
template <typename G>
G Interpolate(const std::vector<double>& table, const G& c) {
  const int n = static_cast<int>(table.size());
  const G x = SafeSqrt(Clamp(c, G(0.0), G(1.0))) * G(n - 1);
  const int k = std::min(n - 2, static_cast<int>(ScalarOf(x)));
  return G(table[k]) + (x - G(k)) * G(table[k + 1] - table[k]);
}

}  // namespace energy_bound_internal

// The factor f' / f at cosines ci = wi.z and co = wo.z: 1 without a bound
// and below the surface (where the models reflect nothing).
template <typename G>
G EnergyBoundFactor(const EnergyBound* b, const G& ci, const G& co) {
  if (b == nullptr || !(ci > G(0.0)) || !(co > G(0.0))) return G(1.0);
  using energy_bound_internal::Interpolate;
  const G fade_cos(kEnergyBoundFadeCos);
  const G fade = Min(G(1.0), ci / fade_cos) * Min(G(1.0), co / fade_cos);
  const G d =
      Max(Max(ci, Interpolate(b->light, ci)), ci * Interpolate(b->view, co));
  return fade * ci / d;
}

namespace energy_bound_internal {

// The largest albedo over azimuth at polar cosine c, per side (light:
// c A_L, the integral of rho(w, l) l.z over l; view: A_V, the integral of
// rho(l, w) over l), by the midpoint rule q: at n_phi azimuths from phi0,
// then halving the step about the largest 3 times (a narrow peak between
// the azimuths).
template <typename Rho>
double LargestAlbedo(const Rho& rho, bool light, double c,
                     const HemisphereQuadrature& q, double phi0, int n_phi) {
  const double s = std::sqrt(std::max(0.0, 1.0 - c * c));
  auto at = [&](double phi) {
    const glm::dvec3 w(s * std::cos(phi), s * std::sin(phi), c);
    glm::dvec3 a(0.0);
    for (size_t i = 0; i < q.w.size(); ++i) {
      a += light ? q.weight[i] * q.w[i].z * rho(w, q.w[i])
                 : q.weight[i] * rho(q.w[i], w);
    }
    return std::max({a.x, a.y, a.z});
  };
  double step = 2.0 * kPi / n_phi, best_phi = phi0, best = -1.0;
  for (int j = 0; j < n_phi; ++j) {
    const double phi = phi0 + step * j, a = at(phi);
    if (a > best) best = a, best_phi = phi;
  }
  for (int level = 0; level < 3; ++level) {
    step *= 0.5;
    const double centre = best_phi;
    for (double phi : {centre - step, centre + step}) {
      const double a = at(phi);
      if (a > best) best = a, best_phi = phi;
    }
  }
  return best;
}

}  // namespace energy_bound_internal

// The bound of a model given by rho(wi, wo) (a callable returning
// glm::dvec3, the cosine-weighted value; every channel is bounded by the
// largest): at each node the largest albedo over azimuth of each side
// (24 azimuths from phi0, radians: a weave's rotation, where its threads'
// peaks are; then refined about the largest), by the midpoint rule
// (models/albedo.h) over 16 rings; beyond 80 degrees, where an albedo
// over 0.5 may be a thread's narrow peak along its axis, over 32 rings
// (the satin's thread at 87 degrees: 16 rings 16 % low, 32 rings 1 %).
// Null when the model needs no bound (every c A_L <= c and A_V <= 1 even
// with the margin).
template <typename Rho>
std::shared_ptr<const EnergyBound> ComputeEnergyBound(const Rho& rho,
                                                      double phi0 = 0.0) {
  using energy_bound_internal::LargestAlbedo;
  constexpr int kAzimuths = 24, kRings = 16, kGrazingRings = 32;
  constexpr double kCos80 = 0.17364817766693033;
  const HemisphereQuadrature coarse = MakeHemisphereQuadrature(kRings);
  const HemisphereQuadrature fine = MakeHemisphereQuadrature(kGrazingRings);
  const int n = kEnergyBoundNodes;
  std::vector<double> light(n, 0.0), view(n, 0.0);
  for (int k = n - 1; k >= 0; --k) {
    const double c = std::max(kEnergyBoundFadeCos, EnergyBoundNode(k, n));
    if (k + 1 < n && EnergyBoundNode(k + 1, n) <= kEnergyBoundFadeCos) {
      light[k] = light[k + 1];  // beyond 87 degrees: the values at 87
      view[k] = view[k + 1];
      continue;
    }
    light[k] = LargestAlbedo(rho, true, c, coarse, phi0, kAzimuths);
    view[k] = LargestAlbedo(rho, false, c, coarse, phi0, kAzimuths);
    if (c < kCos80 && light[k] > 0.5 * c) {
      light[k] = LargestAlbedo(rho, true, c, fine, phi0, kAzimuths);
    }
    if (c < kCos80 && view[k] > 0.5) {
      view[k] = LargestAlbedo(rho, false, c, fine, phi0, kAzimuths);
    }
  }
  auto bound = std::make_shared<EnergyBound>();
  bool needed = false;
  for (int k = 0; k < n; ++k) {
    bound->light.push_back(kEnergyBoundMargin * light[k]);
    bound->view.push_back(kEnergyBoundMargin * view[k]);
    const double c = std::max(kEnergyBoundFadeCos, EnergyBoundNode(k, n));
    needed = needed || bound->light[k] > c || bound->view[k] > 1.0;
  }
  if (!needed) return nullptr;
  return bound;
}

}  // namespace clothfit
