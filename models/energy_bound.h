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
// A Ceres Jet: its value (the position between nodes carries a derivative;
// the node it falls after does not).
template <typename J>
double ScalarOf(const J& x) {
  return ScalarOf(x.a);
}

// The table of n entries (of type V) linearly interpolated at c (clamped
// to [0, 1]) between the nodes c_k = (k / (n - 1))^2, as an R.
template <typename R, typename V, typename G>
R Interpolate(const V* table, int n, const G& c) {
  const G x = SafeSqrt(Clamp(c, G(0.0), G(1.0))) * G(n - 1);
  const int k = std::min(n - 2, static_cast<int>(ScalarOf(x)));
  return R(table[k]) + R(x - G(k)) * (R(table[k + 1]) - R(table[k]));
}

}  // namespace energy_bound_internal

// The factor f' / f at cosines ci = wi.z and co = wo.z of the bound whose
// tables (n entries each) are `light` and `view`, as an R: 1 below the
// surface (where the models reflect nothing). Tables of Jets give the
// factor's derivative through the bound (a fit of the bounded model).
template <typename R, typename V, typename G>
R EnergyBoundFactorOf(const V* light, const V* view, int n, const G& ci,
                      const G& co) {
  if (!(ci > G(0.0)) || !(co > G(0.0))) return R(1.0);
  using energy_bound_internal::Interpolate;
  const G fade_cos(kEnergyBoundFadeCos);
  const R fade(Min(G(1.0), ci / fade_cos) * Min(G(1.0), co / fade_cos));
  const R d = Max(Max(R(ci), Interpolate<R>(light, n, ci)),
                  R(ci) * Interpolate<R>(view, n, co));
  return fade * R(ci) / d;
}

// The same for a bound's tables; 1 without a bound.
template <typename G>
G EnergyBoundFactor(const EnergyBound* b, const G& ci, const G& co) {
  if (b == nullptr) return G(1.0);
  return EnergyBoundFactorOf<G>(b->light.data(), b->view.data(),
                                static_cast<int>(b->light.size()), ci, co);
}

// The largest directional albedo the factor at cosines (ci, co) divides
// by, max(A_L(ci), A_V(co)) from the tables (the fade aside): the factor
// is below 1 (the fade aside) where it exceeds 1.
inline double EnergyBoundAlbedo(const EnergyBound& b, double ci, double co) {
  using energy_bound_internal::Interpolate;
  const int n = static_cast<int>(b.light.size());
  return std::max(Interpolate<double>(b.light.data(), n, ci) / ci,
                  Interpolate<double>(b.view.data(), n, co));
}

// How one entry of a bound's table is computed: the albedo of one channel
// toward one azimuth (radians) by the midpoint rule over `rings` rings, or
// (copy) the next node's entry. ComputeEnergyBound finds the azimuth and
// channel of the largest albedo; with them held, the entry is a smooth
// function of the model's parameters (EnergyBoundTables), whose
// derivative a fit of the bounded model needs. A held entry is taken as
// given where EnergyBoundTables is given values (a fit differentiates only
// the entries that its rows' factors depend on).
struct EnergyBoundEntry {
  double phi = 0.0;
  int channel = 0;
  int rings = 16;
  bool copy = false;
  bool held = false;
  // Other azimuths of the same channel whose albedo may peak above phi's
  // as the parameters move (peaks found there before, in a fit's plan
  // merged from several): RefineEnergyBoundPlan follows each one's crest
  // and takes the largest.
  std::vector<double> others;
};

struct EnergyBoundPlan {
  std::vector<EnergyBoundEntry> light, view;  // kEnergyBoundNodes each
};

namespace energy_bound_internal {

// The node's cosine: beyond 87 degrees the tables hold the values at 87.
inline double NodeCos(int k, int n) {
  return std::max(kEnergyBoundFadeCos, EnergyBoundNode(k, n));
}

// The midpoint rule of `rings` rings (16 or 32), made once.
inline const HemisphereQuadrature& Quadrature(int rings) {
  static const HemisphereQuadrature coarse = MakeHemisphereQuadrature(16);
  static const HemisphereQuadrature fine = MakeHemisphereQuadrature(32);
  return rings > 16 ? fine : coarse;
}

// The albedo of each channel at polar cosine c toward azimuth phi, per side
// (light: c A_L, the integral of rho(w, l) l.z over l; view: A_V, the
// integral of rho(l, w) over l), by the midpoint rule q. rho(wi, wo)
// returns the cosine-weighted value as a Vec3<T>.
template <typename T, typename Rho>
Vec3<T> AlbedoAt(const Rho& rho, bool light, double c, double phi,
                 const HemisphereQuadrature& q) {
  const double s = std::sqrt(std::max(0.0, 1.0 - c * c));
  const glm::dvec3 w(s * std::cos(phi), s * std::sin(phi), c);
  Vec3<T> a(T(0.0));
  for (size_t i = 0; i < q.w.size(); ++i) {
    a += light ? rho(w, q.w[i]) * T(q.weight[i] * q.w[i].z)
               : rho(q.w[i], w) * T(q.weight[i]);
  }
  return a;
}

// The entry of the largest albedo over azimuth and channel at polar cosine
// c: n_phi azimuths from phi0, then the step halved about the largest 3
// times (a narrow peak between the azimuths). Its value goes to *value.
template <typename Rho>
EnergyBoundEntry LargestAlbedo(const Rho& rho, bool light, double c, int rings,
                               double phi0, int n_phi, double* value) {
  const HemisphereQuadrature& q = Quadrature(rings);
  EnergyBoundEntry best{phi0, 0, rings, false, false, {}};
  double best_value = -1.0;
  auto visit = [&](double phi) {
    const glm::dvec3 a = AlbedoAt<double>(rho, light, c, phi, q);
    for (int channel = 0; channel < 3; ++channel) {
      if (a[channel] > best_value) {
        best_value = a[channel];
        best = {phi, channel, rings, false, false, {}};
      }
    }
  };
  double step = 2.0 * kPi / n_phi;
  for (int j = 0; j < n_phi; ++j) visit(phi0 + step * j);
  for (int level = 0; level < 3; ++level) {
    step *= 0.5;
    const double centre = best.phi;
    visit(centre - step);
    visit(centre + step);
  }
  *value = best_value;
  return best;
}

}  // namespace energy_bound_internal

// The tables of `plan` for the model rho (as in AlbedoAt), widened by
// kEnergyBoundMargin: light[k], view[k] for k < kEnergyBoundNodes. With
// `held` (light then view), the held entries are those values instead.
template <typename T, typename Rho>
void EnergyBoundTables(const EnergyBoundPlan& plan, const Rho& rho, T* light,
                       T* view, const double* held = nullptr) {
  using energy_bound_internal::AlbedoAt;
  using energy_bound_internal::NodeCos;
  using energy_bound_internal::Quadrature;
  const int n = static_cast<int>(plan.light.size());
  for (int side = 0; side < 2; ++side) {
    const std::vector<EnergyBoundEntry>& entries =
        side == 0 ? plan.light : plan.view;
    T* out = side == 0 ? light : view;
    for (int k = n - 1; k >= 0; --k) {
      const EnergyBoundEntry& e = entries[k];
      if (e.copy) {
        out[k] = out[k + 1];
        continue;
      }
      if (e.held && held) {
        out[k] = T(held[side * n + k]);
        continue;
      }
      const Vec3<T> a = AlbedoAt<T>(rho, side == 0, NodeCos(k, n), e.phi,
                                    Quadrature(e.rings));
      out[k] = T(kEnergyBoundMargin) * a[e.channel];
    }
  }
}

// The azimuth step of a crest refinement (RefineEnergyBoundPlan): the
// azimuth search's finest step, 360 / 24 / 8 degrees.
inline constexpr double kEnergyBoundCrestStep = 2.0 * kPi / 24.0 / 8.0;

// `plan` with each entry that is derived (neither a copy nor held) moved
// to the crest of its albedo near its azimuth: of the azimuths phi - d,
// phi, phi + d (d = kEnergyBoundCrestStep) and the vertex of the parabola
// through them (within d of phi), the one of the largest albedo of the
// entry's channel; likewise each of its `others`, and the largest crest
// becomes phi (the rest its others). A plan holds an azimuth fixed while
// the parameters move the peak: evaluated through the refined plan at
// every parameter point, a table entry follows the peak's crest, and its
// derivative there is that of the peak itself (the derivative of a
// maximum is that of the maximised function at its argument). A pure
// function of the model and `plan`, so that a fit can reproduce the
// tables it was solved through.
template <typename Rho>
EnergyBoundPlan RefineEnergyBoundPlan(const Rho& rho,
                                      const EnergyBoundPlan& plan) {
  using energy_bound_internal::AlbedoAt;
  using energy_bound_internal::NodeCos;
  using energy_bound_internal::Quadrature;
  EnergyBoundPlan out = plan;
  const int n = static_cast<int>(plan.light.size());
  const double d = kEnergyBoundCrestStep;
  for (int side = 0; side < 2; ++side) {
    std::vector<EnergyBoundEntry>& entries = side == 0 ? out.light : out.view;
    for (int k = 0; k < n; ++k) {
      EnergyBoundEntry& e = entries[k];
      if (e.copy || e.held) continue;
      const double c = NodeCos(k, n);
      const HemisphereQuadrature& q = Quadrature(e.rings);
      auto albedo = [&](double phi) {
        return AlbedoAt<double>(rho, side == 0, c, phi, q)[e.channel];
      };
      // The crest near phi0 and its albedo.
      auto crest = [&](double phi0, double* value) {
        const double a0 = albedo(phi0), am = albedo(phi0 - d),
                     ap = albedo(phi0 + d);
        double best_phi = phi0, best = a0;
        if (am > best) best_phi = phi0 - d, best = am;
        if (ap > best) best_phi = phi0 + d, best = ap;
        const double curvature = am - 2.0 * a0 + ap;
        if (curvature < 0.0) {
          const double t = std::clamp(0.5 * (am - ap) / curvature, -1.0, 1.0);
          const double phi = phi0 + t * d;
          const double a = albedo(phi);
          if (a > best) best_phi = phi, best = a;
        }
        *value = best;
        return best_phi;
      };
      double best = 0.0;
      std::vector<double> crests = {crest(e.phi, &best)};
      for (double other : e.others) {
        double value = 0.0;
        const double phi = crest(other, &value);
        if (value > best) {
          best = value;
          crests.insert(crests.begin(), phi);
        } else {
          crests.push_back(phi);
        }
      }
      e.phi = crests.front();
      e.others.assign(crests.begin() + 1, crests.end());
    }
  }
  return out;
}

// Where the bound of a model given by rho(wi, wo) (a callable returning
// glm::dvec3, the cosine-weighted value; every channel is bounded by the
// largest) takes its entries: at each node the largest albedo over azimuth
// and channel of each side (24 azimuths from phi0, radians: a weave's
// rotation, where its threads' peaks are; then refined about the largest),
// by the midpoint rule (models/albedo.h) over 16 rings; beyond 80 degrees,
// where an albedo over 0.5 may be a thread's narrow peak along its axis,
// over 32 rings (the satin's thread at 87 degrees: 16 rings 16 % low, 32
// rings 1 %); then each entry on its crest (RefineEnergyBoundPlan).
template <typename Rho>
EnergyBoundPlan PlanEnergyBound(const Rho& rho, double phi0 = 0.0) {
  using energy_bound_internal::LargestAlbedo;
  using energy_bound_internal::NodeCos;
  constexpr int kAzimuths = 24, kRings = 16, kGrazingRings = 32;
  constexpr double kCos80 = 0.17364817766693033;
  const int n = kEnergyBoundNodes;
  EnergyBoundPlan plan;
  plan.light.resize(n);
  plan.view.resize(n);
  for (int k = n - 1; k >= 0; --k) {
    if (k + 1 < n && EnergyBoundNode(k + 1, n) <= kEnergyBoundFadeCos) {
      plan.light[k].copy = plan.view[k].copy = true;  // beyond 87 degrees
      continue;
    }
    const double c = NodeCos(k, n);
    for (int side = 0; side < 2; ++side) {
      const bool light = side == 0;
      double a = 0.0;
      EnergyBoundEntry e =
          LargestAlbedo(rho, light, c, kRings, phi0, kAzimuths, &a);
      if (c < kCos80 && a > (light ? 0.5 * c : 0.5)) {
        e = LargestAlbedo(rho, light, c, kGrazingRings, phi0, kAzimuths, &a);
      }
      (light ? plan.light : plan.view)[k] = e;
    }
  }
  return RefineEnergyBoundPlan(rho, plan);  // on the crests
}

// The bound of rho (PlanEnergyBound): null when the model needs none
// (every c A_L <= c and A_V <= 1 even with the margin). `plan_out`, when
// not null, receives the plan.
template <typename Rho>
std::shared_ptr<const EnergyBound> ComputeEnergyBound(
    const Rho& rho, double phi0 = 0.0, EnergyBoundPlan* plan_out = nullptr) {
  EnergyBoundPlan plan = PlanEnergyBound(rho, phi0);
  const int n = kEnergyBoundNodes;
  auto bound = std::make_shared<EnergyBound>();
  bound->light.resize(n);
  bound->view.resize(n);
  EnergyBoundTables<double>(plan, rho, bound->light.data(), bound->view.data());
  bool needed = false;
  for (int k = 0; k < n; ++k) {
    const double c = energy_bound_internal::NodeCos(k, n);
    needed = needed || bound->light[k] > c || bound->view[k] > 1.0;
  }
  if (plan_out) *plan_out = std::move(plan);
  if (!needed) return nullptr;
  return bound;
}

}  // namespace clothfit
