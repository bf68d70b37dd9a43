// Importance sampling of the cloth model (models/microcylinder_cloth.h) for
// path tracers: wi given wo, with its pdf (the slides' future work), in
// any floating-point type R.
//
// The scheme: a one-sample mixture of
//   pdf(wi | wo) = c wi.z / pi                                      (cosine)
//                + (1 - c) sum_j (a_j / A) (1 / T_j) sum_k m_jk(wi)   (cones)
// on the upper hemisphere, with c = kClothCosineWeight, a_j the
// coverages, A = sum_j a_j, T_j the tangent samples of thread j (c = 1
// when A = 0). m_jk is the longitudinal cone of tangent sample k of thread
// j (models/sampling.h ThreadCone: the surface lobe's peak and width),
// mirrored into the upper hemisphere: m(w) = cone(w) + cone(mirror(w)).
// The cosine part covers the volume lobe, the azimuthal factors, the
// diffuse term and the gaps. Every sample lies above the surface; a
// renderer weights it by rho(wi, wo) / pdf.
#pragma once

#include <cmath>

#include "models/microcylinder_cloth.h"
#include "models/sampling.h"

namespace clothfit {

// Share of the cosine-weighted hemisphere in the mixture.
inline constexpr double kClothCosineWeight = 0.5;

struct ClothSample {
  glm::dvec3 wi{0.0, 0.0, 1.0};  // unit, wi.z >= 0
  double pdf = 0.0;              // per steradian, the full mixture
};

namespace cloth_sampling_detail {

template <typename R>
R CoverageSum(const ClothParamsT<R>& cloth) {
  R sum = R(0.0);
  for (const ClothThreadT<R>& th : cloth.threads) sum += th.coverage;
  return sum;
}

template <typename R>
R CosineShare(const R& coverage) {
  return coverage > R(0.0) ? R(kClothCosineWeight) : R(1.0);
}

}  // namespace cloth_sampling_detail

// The mixture's density at wi (unit) given wo (unit), per steradian, for a
// cloth whose sample frames come from `frames` (as in ClothRhoWithFrames:
// frames.Count(j), frames.Get(j, k) and its repeats, frames.Total(j)).
// Zero below the surface.
template <typename R, typename Frames>
R ClothWiPdfWithFrames(const ClothParamsT<R>& cloth, const Frames& frames,
                       const Vec3<R>& wo, const Vec3<R>& wi) {
  if (!(wi.z >= R(0.0))) return R(0.0);
  const R coverage = cloth_sampling_detail::CoverageSum(cloth);
  const R c = cloth_sampling_detail::CosineShare(coverage);
  R pdf = c * CosineHemispherePdf(wi);
  if (!(coverage > R(0.0))) return pdf;
  const Vec3<R> mirrored = MirrorZ(wi);
  for (size_t j = 0; j < cloth.threads.size(); ++j) {
    const ClothThreadT<R>& th = cloth.threads[j];
    const int count = frames.Count(j);
    if (count == 0 || !(th.coverage > R(0.0))) continue;
    const R weight = (R(1.0) - c) * th.coverage / coverage / R(frames.Total(j));
    for (int k = 0; k < count; ++k) {
      const TangentFrame<R> f = frames.Get(j, k);
      const ThreadCone<R> cone =
          MakeThreadCone(f.t, f.n, th.params.gamma_s_deg, wo);
      pdf += weight * R(f.repeats) *
             (ThreadConePdf(cone, wi) + ThreadConePdf(cone, mirrored));
    }
  }
  return pdf;
}

// wi given wo from two uniform numbers in [0, 1): u1 picks the component
// (cosine or a tangent sample's cone) and, rescaled, samples it with u2.
// The density of the returned wi is ClothWiPdfWithFrames (not computed
// here: a renderer that needs it calls it).
template <typename R, typename Frames>
Vec3<R> SampleClothWiWithFrames(const ClothParamsT<R>& cloth,
                                const Frames& frames, const Vec3<R>& wo, R u1,
                                const R& u2) {
  const R coverage = cloth_sampling_detail::CoverageSum(cloth);
  const R c = cloth_sampling_detail::CosineShare(coverage);
  if (u1 < c) return SampleCosineHemisphere(u1 / c, u2);
  // The first tangent sample whose share of [c, 1) reaches u1 (the last one
  // if rounding leaves u1 beyond them all).
  R x = (u1 - c) / (R(1.0) - c) * coverage;
  const ClothThreadT<R>* chosen = nullptr;
  TangentFrame<R> frame;
  R v = R(0.0);
  for (size_t j = 0; j < cloth.threads.size() && x >= R(0.0); ++j) {
    const ClothThreadT<R>& th = cloth.threads[j];
    const int count = frames.Count(j);
    if (count == 0 || !(th.coverage > R(0.0))) continue;
    const R per_sample = th.coverage / R(frames.Total(j));
    for (int k = 0; k < count && x >= R(0.0); ++k) {
      chosen = &th;
      frame = frames.Get(j, k);
      const R step = per_sample * R(frame.repeats);
      v = Clamp(x / step, R(0.0), kOneBelow<R>);
      x -= step;
    }
  }
  if (chosen == nullptr) return SampleCosineHemisphere(u1, u2);  // A = 0
  const ThreadCone<R> cone =
      MakeThreadCone(frame.t, frame.n, chosen->params.gamma_s_deg, wo);
  return MirrorToUpper(SampleThreadCone(cone, v, u2));
}

// The same for a cloth's parameters (frames made on the fly).
inline double ClothWiPdf(const ClothParams& cloth, const glm::dvec3& wo,
                         const glm::dvec3& wi) {
  return ClothWiPdfWithFrames(cloth, ClothFramesOnTheFly<double>{cloth}, wo,
                              wi);
}

inline ClothSample SampleClothWi(const ClothParams& cloth, const glm::dvec3& wo,
                                 double u1, double u2) {
  const ClothFramesOnTheFly<double> frames{cloth};
  ClothSample out;
  out.wi = SampleClothWiWithFrames(cloth, frames, wo, u1, u2);
  out.pdf = ClothWiPdfWithFrames(cloth, frames, wo, out.wi);
  return out;
}

}  // namespace clothfit
