// Directional albedo: the white-furnace quantity of a reflectance model
// (pbrt-v4, Section 4.3.1, the hemispherical-directional reflectance;
// Mitsuba 3's furnace tests). With rho = f wi.z,
//
//   a(wo) = integral over wi.z > 0 of rho(wi, wo) dw_i,
//
// the radiance a surface sends toward wo under a uniform white sky of unit
// radiance, which is what a path tracer's estimator averages for a camera
// ray wo. A passive surface element conserves energy when a(wo) <= 1 in
// every channel at every wo. (The light side, the integral of
// f(wi, wo) wo.z over wo, equals it for a reciprocal model; for the
// Lafortune texels of Daubert et al. 2001, whose foreshortening is taken
// about a tilted texel normal, it exceeds 1 at grazing light by design: a
// facet tilted toward the light receives more than the macro-surface.)
//
// Any model: a midpoint rule over the hemisphere (HemisphereQuadrature).
// Lafortune lobes: in closed form up to a one-dimensional integral
// (LafortuneViewAlbedo), since a lobe [C . (l * v)]^N is, for a fixed v,
// the cosine lobe [w . l]^N of the vector w = C * v (Lafortune et al.
// 1997, Section 3): its integral against l.z depends only on |w|, N and
// the angle between w and the normal.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "models/lafortune.h"
#include "models/math.h"

namespace clothfit {

// Directions and solid-angle weights of a midpoint rule on the upper
// hemisphere: n_theta rings of equal polar angle, 2 n_theta azimuths
// each, weight sin(theta) dtheta dphi (the weights sum to 2 pi within
// O(1/n_theta^2)).
struct HemisphereQuadrature {
  std::vector<glm::dvec3> w;
  std::vector<double> weight;
};

inline HemisphereQuadrature MakeHemisphereQuadrature(int n_theta) {
  HemisphereQuadrature q;
  const int n_phi = 2 * n_theta;
  const double dt = 0.5 * kPi / n_theta, dp = 2.0 * kPi / n_phi;
  for (int i = 0; i < n_theta; ++i) {
    const double theta = (i + 0.5) * dt;
    for (int j = 0; j < n_phi; ++j) {
      const double phi = (j + 0.5) * dp;
      q.w.emplace_back(std::sin(theta) * std::cos(phi),
                       std::sin(theta) * std::sin(phi), std::cos(theta));
      q.weight.push_back(std::sin(theta) * dt * dp);
    }
  }
  return q;
}

// The directions a furnace check visits: the normal, then rings at the
// given polar angles (degrees; the last near grazing) with n_phi azimuths
// each.
inline std::vector<glm::dvec3> FurnaceDirections(
    int n_phi,
    const std::vector<double>& theta_deg = {15, 30, 45, 60, 70, 80, 85, 89}) {
  std::vector<glm::dvec3> out = {glm::dvec3(0.0, 0.0, 1.0)};
  for (double t : theta_deg) {
    const double theta = t * kPi / 180.0;
    for (int j = 0; j < n_phi; ++j) {
      const double phi = 2.0 * kPi * j / n_phi;
      out.emplace_back(std::sin(theta) * std::cos(phi),
                       std::sin(theta) * std::sin(phi), std::cos(theta));
    }
  }
  return out;
}

// a(wo) of rho(wi, wo) (a callable returning glm::dvec3, the
// cosine-weighted value) by the quadrature q.
template <typename Rho>
glm::dvec3 QuadratureViewAlbedo(const Rho& rho, const glm::dvec3& wo,
                                const HemisphereQuadrature& q) {
  glm::dvec3 a(0.0);
  for (size_t i = 0; i < q.w.size(); ++i) a += q.weight[i] * rho(q.w[i], wo);
  return a;
}

// G(N, c) = integral over {l : l . m > 0} of (l . m) [u . l]_+^N dw_l for
// unit vectors u, m with u . m = c: the albedo of a unit cosine lobe about
// u, cut by the plane normal to m. G(N, 1) = 2 pi / (N + 2) and
// G <= 2 pi / (N + 1) for every c. With t = u . l, the azimuthal integral
// about u has a closed form, J(t) = integral of (c t + s sqrt(1 - t^2)
// cos b)_+ db (s = sqrt(1 - c^2)); the remaining integral of t^N J(t) over
// [0, 1] is taken after substituting x = t^(N + 1), which spreads the
// lobe's peak over [0, 1], by the midpoint rule (LobeNodes: its nodes t_j
// for one N, which every c shares).
struct LobeNodes {
  double n = 0.0;
  std::vector<double> t, sin_t;  // t_j and sqrt(1 - t_j^2)

  explicit LobeNodes(double exponent, int nodes = 48) : n(exponent) {
    for (int j = 0; j < nodes; ++j) {
      t.push_back(std::pow((j + 0.5) / nodes, 1.0 / (n + 1.0)));
      sin_t.push_back(std::sqrt(std::max(0.0, 1.0 - t.back() * t.back())));
    }
  }

  double Integral(double c) const {
    c = std::clamp(c, -1.0, 1.0);
    const double s = std::sqrt(std::max(0.0, 1.0 - c * c));
    double sum = 0.0;
    for (size_t j = 0; j < t.size(); ++j) {
      const double a = c * t[j], b = s * sin_t[j];
      if (b <= std::abs(a)) {
        sum += a > 0.0 ? 2.0 * kPi * a : 0.0;
      } else {
        sum += 2.0 * (a * std::acos(-a / b) + std::sqrt(b * b - a * a));
      }
    }
    return sum / (t.size() * (n + 1.0));
  }
};

inline double LobeCosineIntegral(double n, double c, int nodes = 48) {
  return LobeNodes(n, nodes).Integral(c);
}

// The integral of l.z [rho_d + sum_k (C_k . (l * d))_+^N_k] over the
// texel's hemisphere l.z > 0 (the bracket of eq. 2 against the
// foreshortening, d fixed), per channel: pi rho_d plus each lobe's
// |w|^N G(N, w.m / |w|) with w = C * d (LobeCosineIntegral). `m`: the
// normal of the plane that cuts the lobes and weights them, in the texel's
// frame (+z: the texel's own). LafortuneBracketAlbedos: the same for many
// directions, each lobe's nodes computed once.
inline std::vector<glm::dvec3> LafortuneBracketAlbedos(
    const LafortuneParams& p, const std::vector<glm::dvec3>& d,
    const std::vector<glm::dvec3>& m) {
  std::vector<glm::dvec3> a(d.size(), kPi * p.diffuse);
  for (const LafortuneLobe& lobe : p.lobes) {
    for (int c = 0; c < 3; ++c) {
      const LobeNodes nodes(lobe.n[c]);
      for (size_t i = 0; i < d.size(); ++i) {
        const glm::dvec3 w(lobe.cx[c] * d[i].x, lobe.cy[c] * d[i].y,
                           lobe.cz[c] * d[i].z);
        const double len = glm::length(w);
        if (!(len > 0.0)) continue;
        a[i][c] +=
            std::pow(len, lobe.n[c]) * nodes.Integral(glm::dot(w, m[i]) / len);
      }
    }
  }
  return a;
}
inline glm::dvec3 LafortuneBracketAlbedo(
    const LafortuneParams& p, const glm::dvec3& d,
    const glm::dvec3& m = glm::dvec3(0.0, 0.0, 1.0)) {
  return LafortuneBracketAlbedos(p, {d}, {m})[0];
}

// The view-side albedo a(v) of a Lafortune texel (v in the surface frame):
// T(v) times the bracket's albedo at the view in the texel's frame. Exact
// (up to LobeCosineIntegral's quadrature) for a texel whose normal is the
// surface's; for a tilted texel an upper bound (the model is zero for
// lights below the surface, which the texel's hemisphere includes).
inline glm::dvec3 LafortuneViewAlbedo(const LafortuneModel& m,
                                      const glm::dvec3& v) {
  if (!(v.z > 0.0)) return glm::dvec3(0.0);
  const TexelFrame frame = MakeTexelFrame(m.normal);
  return LookupView(m.lut, v).color *
         LafortuneBracketAlbedo(m.params, ToTexelFrame(frame, v));
}

}  // namespace clothfit
