// Importance sampling of the cloth model (models/microcylinder_cloth.h) for
// path tracers: wi given wo, with its pdf (the slides' future work).
// Double precision only (sampling is not fitted, so no Jets).
//
// The scheme: a one-sample mixture over the whole sphere of directions,
//   pdf(wi | wo) = c wi.z / pi [wi.z > 0]                          (cosine)
//                + (1 - c) sum_j (a_j / A) (1 / T_j) sum_k p_jk(wi)   (lobes)
// with c = kClothCosineWeight, a_j the coverages, A = sum_j a_j, T_j the
// tangent samples of thread j (c = 1 when A = 0). p_jk is the specular cone
// of tangent sample k of thread j (tangent t, SPEC §3.2): the surface lobe
// g(gamma_s, theta_h) of eq. 3 peaks where theta_i = -theta_o (theta =
// asin(w.t), the longitudinal angle) and, as theta_h = (theta_i +
// theta_o) / 2, has width 2 gamma_s in theta_i. So
//   theta_i ~ logistic(mu = -theta_o, s = 2 gamma_s sqrt(3) / pi),
//             truncated to [-pi/2, pi/2] (same standard deviation as the
//             Gaussian; heavier tails, and a closed-form inverse CDF),
//   phi     ~ uniform in [0, 2 pi) around t (the volume lobe and the
//             azimuthal factors are left to the cosine part),
// and with d omega = cos(theta) d theta d phi about the axis t,
//   p_jk(wi) = L(theta_i) / (2 pi cos theta_i),
//   L(x) = e^-|z| / (s (1 + e^-|z|)^2) / (F(pi/2) - F(-pi/2)), z = (x-mu)/s,
//   F(x) = 1 / (1 + e^-z).
// Lobe samples can fall below the surface (wi.z <= 0), where rho = 0: the
// pdf is a density on the whole sphere and such a sample has weight 0.
// A renderer weights a sample by rho(wi, wo) / pdf = ClothRho / pdf.
#pragma once

#include <cmath>

#include "models/microcylinder_cloth.h"

namespace clothfit {

// Share of the cosine-weighted hemisphere in the mixture.
inline constexpr double kClothCosineWeight = 0.5;

struct ClothSample {
  glm::dvec3 wi{0.0, 0.0, 1.0};  // unit; may be below the surface
  double pdf = 0.0;              // per steradian, the full mixture
};

namespace cloth_sampling_detail {

// The cone of one tangent sample: axis t, a frame (e1, e2) of its normal
// plane, and the truncated logistic in theta.
struct Cone {
  glm::dvec3 t, e1, e2;
  double mu = 0.0, s = 1.0, f_lo = 0.0, f_hi = 1.0;
};

inline double LogisticCdf(double x, double mu, double s) {
  return 1.0 / (1.0 + std::exp(-(x - mu) / s));
}

inline Cone MakeCone(const ClothThread& th, double rotation_deg,
                     double offset_deg, const glm::dvec3& wo) {
  const glm::dvec3 d = ThreadAxis(th.direction, rotation_deg);
  const glm::dvec3 z(0.0, 0.0, 1.0);
  const double psi = Radians(offset_deg);
  Cone c;
  c.t = d * std::cos(psi) + z * std::sin(psi);
  c.e1 = z * std::cos(psi) - d * std::sin(psi);
  c.e2 = glm::cross(c.t, c.e1);
  c.mu = -std::asin(Clamp(glm::dot(wo, c.t), -1.0, 1.0));
  c.s = 2.0 * Radians(th.params.gamma_s_deg) * std::sqrt(3.0) / kPi;
  c.f_lo = LogisticCdf(-0.5 * kPi, c.mu, c.s);
  c.f_hi = LogisticCdf(0.5 * kPi, c.mu, c.s);
  return c;
}

inline double ConePdf(const Cone& c, const glm::dvec3& wi) {
  const double sin_theta = Clamp(glm::dot(wi, c.t), -1.0, 1.0);
  const double cos_theta = std::sqrt(Max(1.0 - sin_theta * sin_theta, 0.0));
  if (!(cos_theta > 0.0)) return 0.0;  // the axis itself: a null set
  const double e = std::exp(-std::abs(std::asin(sin_theta) - c.mu) / c.s);
  const double logistic = e / (c.s * (1.0 + e) * (1.0 + e));
  return logistic / (c.f_hi - c.f_lo) / (2.0 * kPi * cos_theta);
}

inline glm::dvec3 SampleCone(const Cone& c, double u1, double u2) {
  const double f = c.f_lo + u1 * (c.f_hi - c.f_lo);
  const double theta =
      Clamp(c.mu + c.s * std::log(f / (1.0 - f)), -0.5 * kPi, 0.5 * kPi);
  const double phi = 2.0 * kPi * u2;
  return std::sin(theta) * c.t +
         std::cos(theta) * (std::cos(phi) * c.e1 + std::sin(phi) * c.e2);
}

inline double CoverageSum(const ClothParams& cloth) {
  double sum = 0.0;
  for (const ClothThread& th : cloth.threads) sum += th.coverage;
  return sum;
}

}  // namespace cloth_sampling_detail

// The mixture's density at wi (unit) given wo (unit), per steradian.
inline double ClothWiPdf(const ClothParams& cloth, const glm::dvec3& wo,
                         const glm::dvec3& wi) {
  const double coverage = cloth_sampling_detail::CoverageSum(cloth);
  const double c = coverage > 0.0 ? kClothCosineWeight : 1.0;
  double pdf = wi.z > 0.0 ? c * wi.z / kPi : 0.0;
  if (!(coverage > 0.0)) return pdf;
  for (const ClothThread& th : cloth.threads) {
    if (th.offsets_deg.empty()) continue;
    const double weight =
        (1.0 - c) * th.coverage / coverage / th.offsets_deg.size();
    if (!(weight > 0.0)) continue;
    for (double offset : th.offsets_deg) {
      pdf += weight * cloth_sampling_detail::ConePdf(
                          cloth_sampling_detail::MakeCone(
                              th, cloth.rotation_deg, offset, wo),
                          wi);
    }
  }
  return pdf;
}

// wi given wo from three uniform numbers in [0, 1): u0 picks the component
// (cosine or a tangent sample's cone), (u1, u2) the direction within it.
inline ClothSample SampleClothWi(const ClothParams& cloth, const glm::dvec3& wo,
                                 double u0, double u1, double u2) {
  const double coverage = cloth_sampling_detail::CoverageSum(cloth);
  const double c = coverage > 0.0 ? kClothCosineWeight : 1.0;
  ClothSample out;
  if (u0 < c) {  // cosine-weighted hemisphere (Malley's method)
    const double r = std::sqrt(u1), phi = 2.0 * kPi * u2;
    out.wi = glm::dvec3(r * std::cos(phi), r * std::sin(phi),
                        std::sqrt(Max(1.0 - u1, 0.0)));
  } else {
    // The cone of the first tangent sample whose share of [c, 1) reaches
    // u0 (the last one if rounding leaves u0 beyond them all).
    double x = (u0 - c) / (1.0 - c) * coverage;
    const ClothThread* chosen = nullptr;
    double chosen_offset = 0.0;
    for (const ClothThread& th : cloth.threads) {
      if (!(th.coverage > 0.0) || th.offsets_deg.empty()) continue;
      const double step = th.coverage / th.offsets_deg.size();
      for (double offset : th.offsets_deg) {
        if (x < 0.0) break;
        chosen = &th;
        chosen_offset = offset;
        x -= step;
      }
    }
    if (chosen != nullptr) {
      out.wi = cloth_sampling_detail::SampleCone(
          cloth_sampling_detail::MakeCone(*chosen, cloth.rotation_deg,
                                          chosen_offset, wo),
          u1, u2);
    }
  }
  out.pdf = ClothWiPdf(cloth, wo, out.wi);
  return out;
}

}  // namespace clothfit
