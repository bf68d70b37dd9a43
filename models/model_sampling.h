// Importance sampling of every model for path tracers (api/material.h
// Sample and Pdf): wi given wo, from two uniform numbers, and the density
// of the continuous part, in any floating-point type R. Each model's
// sampler is a one-sample mixture of the building blocks in
// models/sampling.h whose shares follow the model's parameters; the
// mixture always keeps a cosine-weighted part, so the density is positive
// wherever the model's value can be, and a path tracer's estimate
// f |wi.z| / pdf is finite. Per model:
//
// - thread (thread frame, tangent +x, whole sphere; the thread scatters to
//   both sides): 1/2 cosine-weighted on the hemisphere of either side
//   (|w.z| / (2 pi)), 1/2 the longitudinal cone of the surface lobe about
//   the tangent (models/sampling.h ThreadCone).
// - cloth: models/cloth_sampling.h (upper hemisphere).
// - Lafortune (upper hemisphere): lobe k, with its channels' mean C and N,
//   is [C . (l' * v')]^N = |u|^N (l'.a)^N with u = (Cx v'x, Cy v'y, Cz v'z)
//   and a = u / |u| in the texel's frame: a cosine-power lobe about a
//   (Lafortune and Willems 1994), sampled exactly and mirrored into the
//   upper hemisphere. Shares: the cosine part 0.1 + 0.9 E_d / E, lobe k
//   the rest in proportion to E_k, with E_d = pi rho_d and E_k = |u|^N
//   2 pi / (N + 2) max(a.z, 0.05) (the lobe's cosine-weighted integral
//   when a = +z), E = E_d + sum_k E_k. The lookup table T(v) scales every
//   part alike and is left out.
// - slab (either side): direct transmission, a delta at wi = -wo, with
//   probability P = T / (T + 2 S), T the channels' mean of exp(-tau /
//   |wo.z|), S = mean(albedo (1 - exp(-tau / |wo.z|))) / 2 (single
//   scattering sends about half of the scattered light to each side); the
//   rest 1/2 cosine-weighted on wo's side (reflection), 1/2 on the other
//   (transmission).
// - sheen (glTF): 3/4 cosine-weighted (the sheen, the diffuse base), 1/4
//   reflection about a GGX half vector of the base's roughness, mirrored
//   into the upper hemisphere.
// - holes: the layer transmits straight through (models/holes_tile.h): a
//   delta at wi = -wo with probability 1, weight its transmittance.
//
// WiPdf is the continuous part's density: it integrates over the sphere to
// 1 - P (the share of the samples that are not a delta).
#pragma once

#include <cmath>
#include <limits>
#include <type_traits>
#include <variant>

#include "models/cloth_sampling.h"
#include "models/prepared.h"
#include "models/sampling.h"

namespace clothfit {

namespace model_sampling_detail {

template <typename R>
R Mean(const Vec3<R>& v) {
  return (v.x + v.y + v.z) / R(3.0);
}

// Cosine-weighted on the side of sign(side) (+z when side >= 0).
template <typename R>
Vec3<R> SampleCosineSide(const R& side, const R& u1, const R& u2) {
  const Vec3<R> w = SampleCosineHemisphere(u1, u2);
  return side >= R(0.0) ? w : MirrorZ(w);
}

template <typename R>
R CosineSidePdf(const R& side, const Vec3<R>& w) {
  return CosineHemispherePdf(side >= R(0.0) ? w : MirrorZ(w));
}

// A Lafortune lobe as a cosine-power lobe seen from the texel-frame view
// v (see the file comment): axis a in the surface frame, exponent N,
// share E_k (0 when the lobe cannot reflect v).
template <typename R>
struct PhongPart {
  Vec3<R> axis;
  R exponent = R(1.0), energy = R(0.0);
};

template <typename R>
PhongPart<R> LobePart(const LafortuneLobeT<R>& lobe,
                      const TexelFrameT<R>& frame, const Vec3<R>& v) {
  using std::pow;
  using std::sqrt;
  PhongPart<R> part;
  const Vec3<R> u(Mean(lobe.cx) * v.x, Mean(lobe.cy) * v.y,
                  Mean(lobe.cz) * v.z);
  const R length = sqrt(glm::dot(u, u));
  if (!(length > R(0.0))) return part;
  const Vec3<R> a = u / length;
  part.axis = frame.t * a.x + frame.b * a.y + frame.n * a.z;
  part.exponent = Max(Mean(lobe.n), R(0.0));
  part.energy = pow(length, part.exponent) * R(2.0 * kPi) /
                (part.exponent + R(2.0)) * Max(part.axis.z, R(0.05));
  if (!(part.energy < std::numeric_limits<R>::max())) {
    part.energy = std::numeric_limits<R>::max();  // also NaN
  }
  return part;
}

// The cosine share and the lobes' total share E - E_d of a Lafortune texel.
template <typename R>
R LafortuneLobeEnergy(const LafortuneParamsT<R>& p, const TexelFrameT<R>& f,
                      const Vec3<R>& v) {
  R sum = R(0.0);
  for (const LafortuneLobeT<R>& lobe : p.lobes) {
    sum = Min(sum + LobePart(lobe, f, v).energy, std::numeric_limits<R>::max());
  }
  return sum;
}

template <typename R>
R LafortuneCosineShare(const LafortuneParamsT<R>& p, const R& lobes) {
  if (!(lobes > R(0.0))) return R(1.0);
  const R diffuse = R(kPi) * Max(Mean(p.diffuse), R(0.0));
  return R(0.1) + R(0.9) * diffuse / (diffuse + lobes);
}

}  // namespace model_sampling_detail

// ---- thread ----
template <typename R>
R DeltaShare(const ThreadParamsT<R>&, const Vec3<R>&) {
  return R(0.0);
}

template <typename R>
ThreadCone<R> ThreadAlongX(const ThreadParamsT<R>& p, const Vec3<R>& wo) {
  return MakeThreadCone(Vec3<R>(R(1.0), R(0.0), R(0.0)),
                        Vec3<R>(R(0.0), R(0.0), R(1.0)), p.gamma_s_deg, wo);
}

template <typename R>
Vec3<R> SampleWiContinuous(const ThreadParamsT<R>& p, const Vec3<R>& wo, R u1,
                           const R& u2) {
  using model_sampling_detail::SampleCosineSide;
  if (u1 < R(0.25)) return SampleCosineSide(R(1.0), u1 * R(4.0), u2);
  if (u1 < R(0.5)) return SampleCosineSide(R(-1.0), u1 * R(4.0) - R(1.0), u2);
  u1 = Clamp(u1 * R(2.0) - R(1.0), R(0.0), kOneBelow<R>);
  return SampleThreadCone(ThreadAlongX(p, wo), u1, u2);
}

template <typename R>
R WiPdf(const ThreadParamsT<R>& p, const Vec3<R>& wo, const Vec3<R>& wi) {
  using std::abs;
  return R(0.5) * abs(wi.z) * R(0.5 / kPi) +
         R(0.5) * ThreadConePdf(ThreadAlongX(p, wo), wi);
}

// ---- cloth ----
template <typename R>
R DeltaShare(const ClothParamsT<R>&, const Vec3<R>&) {
  return R(0.0);
}
template <typename R>
R DeltaShare(const PreparedCloth<R>&, const Vec3<R>&) {
  return R(0.0);
}

inline glm::dvec3 SampleWiContinuous(const ClothParams& c, const glm::dvec3& wo,
                                     double u1, double u2) {
  return SampleClothWiWithFrames(c, ClothFramesOnTheFly<double>{c}, wo, u1, u2);
}
inline double WiPdf(const ClothParams& c, const glm::dvec3& wo,
                    const glm::dvec3& wi) {
  return ClothWiPdf(c, wo, wi);
}

template <typename R>
Vec3<R> SampleWiContinuous(const PreparedCloth<R>& c, const Vec3<R>& wo, R u1,
                           const R& u2) {
  return SampleClothWiWithFrames(c.cloth, c, wo, u1, u2);
}
template <typename R>
R WiPdf(const PreparedCloth<R>& c, const Vec3<R>& wo, const Vec3<R>& wi) {
  return ClothWiPdfWithFrames(c.cloth, c, wo, wi);
}

// ---- Lafortune ----
template <typename R>
Vec3<R> SampleLafortuneWi(const LafortuneParamsT<R>& p, const TexelFrameT<R>& f,
                          const Vec3<R>& wo, R u1, const R& u2) {
  using namespace model_sampling_detail;
  const Vec3<R> v = ToTexelFrame(f, wo);
  const R lobes = LafortuneLobeEnergy(p, f, v);
  const R c = LafortuneCosineShare(p, lobes);
  if (u1 < c) return SampleCosineHemisphere(u1 / c, u2);
  R x = (u1 - c) / (R(1.0) - c) * lobes;
  PhongPart<R> chosen;
  R w = R(0.0);
  for (const LafortuneLobeT<R>& lobe : p.lobes) {
    const PhongPart<R> part = LobePart(lobe, f, v);
    if (!(part.energy > R(0.0))) continue;
    chosen = part;
    w = Clamp(x / part.energy, R(0.0), kOneBelow<R>);
    x -= part.energy;
    if (x < R(0.0)) break;
  }
  if (!(chosen.energy > R(0.0))) return SampleCosineHemisphere(u1, u2);
  return MirrorToUpper(SamplePhongLobe(chosen.axis, chosen.exponent, w, u2));
}

template <typename R>
R LafortuneWiPdf(const LafortuneParamsT<R>& p, const TexelFrameT<R>& f,
                 const Vec3<R>& wo, const Vec3<R>& wi) {
  using namespace model_sampling_detail;
  if (!(wi.z >= R(0.0))) return R(0.0);
  const Vec3<R> v = ToTexelFrame(f, wo);
  const R lobes = LafortuneLobeEnergy(p, f, v);
  const R c = LafortuneCosineShare(p, lobes);
  R pdf = c * CosineHemispherePdf(wi);
  if (!(lobes > R(0.0))) return pdf;
  const Vec3<R> mirrored = MirrorZ(wi);
  for (const LafortuneLobeT<R>& lobe : p.lobes) {
    const PhongPart<R> part = LobePart(lobe, f, v);
    if (!(part.energy > R(0.0))) continue;
    pdf += (R(1.0) - c) * (part.energy / lobes) *
           (PhongLobePdf(part.axis, part.exponent, wi) +
            PhongLobePdf(part.axis, part.exponent, mirrored));
  }
  return pdf;
}

inline double DeltaShare(const LafortuneModel&, const glm::dvec3&) {
  return 0.0;
}
inline glm::dvec3 SampleWiContinuous(const LafortuneModel& m,
                                     const glm::dvec3& wo, double u1,
                                     double u2) {
  return SampleLafortuneWi(m.params, MakeTexelFrame(m.normal), wo, u1, u2);
}
inline double WiPdf(const LafortuneModel& m, const glm::dvec3& wo,
                    const glm::dvec3& wi) {
  return LafortuneWiPdf(m.params, MakeTexelFrame(m.normal), wo, wi);
}

template <typename R>
R DeltaShare(const PreparedLafortune<R>&, const Vec3<R>&) {
  return R(0.0);
}
template <typename R>
Vec3<R> SampleWiContinuous(const PreparedLafortune<R>& m, const Vec3<R>& wo,
                           R u1, const R& u2) {
  return SampleLafortuneWi(m.params, m.frame, wo, u1, u2);
}
template <typename R>
R WiPdf(const PreparedLafortune<R>& m, const Vec3<R>& wo, const Vec3<R>& wi) {
  return LafortuneWiPdf(m.params, m.frame, wo, wi);
}

// ---- slab ----
template <typename R>
R DeltaShare(const SlabParamsT<R>& p, const Vec3<R>& wo) {
  using model_sampling_detail::Mean;
  const Vec3<R> direct = SlabDirectTransmittance(p, wo);
  const R t = Mean(direct);
  const R s = R(0.5) * Mean(p.albedo * (Vec3<R>(R(1.0)) - direct));
  return t + s > R(0.0) ? t / (t + R(2.0) * s) : R(0.0);
}

template <typename R>
Vec3<R> SampleWiContinuous(const SlabParamsT<R>&, const Vec3<R>& wo, R u1,
                           const R& u2) {
  using model_sampling_detail::SampleCosineSide;
  const R side = wo.z >= R(0.0) ? R(1.0) : R(-1.0);
  if (u1 < R(0.5)) return SampleCosineSide(side, u1 * R(2.0), u2);
  u1 = Clamp(u1 * R(2.0) - R(1.0), R(0.0), kOneBelow<R>);
  return SampleCosineSide(-side, u1, u2);
}

template <typename R>
R WiPdf(const SlabParamsT<R>& p, const Vec3<R>& wo, const Vec3<R>& wi) {
  using std::abs;
  return (R(1.0) - DeltaShare(p, wo)) * R(0.5) * abs(wi.z) * R(1.0 / kPi);
}

// ---- holes ----
inline double DeltaShare(const HolesModel&, const glm::dvec3&) { return 1.0; }
inline glm::dvec3 SampleWiContinuous(const HolesModel&, const glm::dvec3& wo,
                                     double, double) {
  return -wo;  // not reached: every sample is the delta
}
inline double WiPdf(const HolesModel&, const glm::dvec3&, const glm::dvec3&) {
  return 0.0;
}

// ---- sheen (the glTF material) ----
template <typename R>
R DeltaShare(const SheenParamsT<R>&, const Vec3<R>&) {
  return R(0.0);
}

template <typename R>
Vec3<R> SampleWiContinuous(const SheenParamsT<R>& p, const Vec3<R>& wo, R u1,
                           const R& u2) {
  if (u1 < R(0.75)) return SampleCosineHemisphere(u1 / R(0.75), u2);
  u1 = Clamp((u1 - R(0.75)) * R(4.0), R(0.0), kOneBelow<R>);
  return MirrorToUpper(
      SampleGgxReflection(p.roughness * p.roughness, wo, u1, u2));
}

template <typename R>
R WiPdf(const SheenParamsT<R>& p, const Vec3<R>& wo, const Vec3<R>& wi) {
  if (!(wi.z >= R(0.0))) return R(0.0);
  const R alpha = p.roughness * p.roughness;
  return R(0.75) * CosineHemispherePdf(wi) +
         R(0.25) * (GgxReflectionPdf(alpha, wo, wi) +
                    GgxReflectionPdf(alpha, wo, MirrorZ(wi)));
}

// ---- every model ----

// The light a delta sample carries, per channel: the direct transmittance
// (slab, holes); 0 for the models without one.
template <typename M, typename R>
Vec3<R> DeltaTransmittance(const M& m, const Vec3<R>& wo) {
  if constexpr (std::is_same_v<M, SlabParams> ||
                std::is_same_v<M, HolesModel>) {
    return Vec3<R>(Transmittance(m, glm::dvec3(wo)));
  } else {
    return Vec3<R>(R(0.0));
  }
}

// wi given wo from (u1, u2) in [0, 1)^2: with probability DeltaShare the
// delta (wi = -wo, pdf = that probability), else u1 rescaled samples the
// continuous part (pdf = WiPdf).
template <typename M, typename R>
DirectionSample<R> SampleWi(const M& m, const Vec3<R>& wo, R u1, const R& u2) {
  DirectionSample<R> out;
  const R delta = DeltaShare(m, wo);
  if (u1 < delta) {
    out.wi = -wo;
    out.pdf = delta;
    out.delta = true;
    return out;
  }
  u1 = Clamp((u1 - delta) / (R(1.0) - delta), R(0.0), kOneBelow<R>);
  out.wi = SampleWiContinuous(m, wo, u1, u2);
  out.pdf = WiPdf(m, wo, out.wi);
  return out;
}

// ---- a prepared model (models/prepared.h), as api/material.h holds it ----
// The parts kept in double (slab, holes, a float Lafortune beyond float's
// range) are sampled in double and rounded to R.

namespace model_sampling_detail {

template <typename R, typename F>
auto VisitPrepared(const PreparedModel<R>& model, const F& f) {
  return std::visit(
      [&](const auto& p) {
        using P = std::decay_t<decltype(p)>;
        if constexpr (std::is_same_v<P, ModelParams>) {
          return std::visit([&](const auto& q) { return f(q); }, p);
        } else {
          return f(p);
        }
      },
      model);
}

// The scalar type a prepared alternative P of PreparedModel<R> is sampled
// in: R for the prepared forms, double for the double parameters.
template <typename P, typename R>
using SamplerScalar =
    std::conditional_t<std::is_same_v<P, ThreadParamsT<R>> ||
                           std::is_same_v<P, SheenParamsT<R>> ||
                           std::is_same_v<P, PreparedCloth<R>> ||
                           std::is_same_v<P, PreparedLafortune<R>>,
                       R, double>;

}  // namespace model_sampling_detail

template <typename R>
DirectionSample<R> SamplePreparedWi(const PreparedModel<R>& model,
                                    const Vec3<R>& wo, const R& u1,
                                    const R& u2) {
  return model_sampling_detail::VisitPrepared(
      model, [&](const auto& p) -> DirectionSample<R> {
        using S =
            model_sampling_detail::SamplerScalar<std::decay_t<decltype(p)>, R>;
        const DirectionSample<S> s = SampleWi(p, Vec3<S>(wo), S(u1), S(u2));
        DirectionSample<R> out;
        out.wi = Vec3<R>(s.wi);
        out.pdf = R(s.pdf);
        out.delta = s.delta;
        return out;
      });
}

template <typename R>
R PreparedWiPdf(const PreparedModel<R>& model, const Vec3<R>& wo,
                const Vec3<R>& wi) {
  return model_sampling_detail::VisitPrepared(model, [&](const auto& p) -> R {
    using S =
        model_sampling_detail::SamplerScalar<std::decay_t<decltype(p)>, R>;
    return R(WiPdf(p, Vec3<S>(wo), Vec3<S>(wi)));
  });
}

template <typename R>
R PreparedDeltaShare(const PreparedModel<R>& model, const Vec3<R>& wo) {
  return model_sampling_detail::VisitPrepared(model, [&](const auto& p) -> R {
    using S =
        model_sampling_detail::SamplerScalar<std::decay_t<decltype(p)>, R>;
    return R(DeltaShare(p, Vec3<S>(wo)));
  });
}

template <typename R>
Vec3<R> PreparedDeltaTransmittance(const PreparedModel<R>& model,
                                   const Vec3<R>& wo) {
  return model_sampling_detail::VisitPrepared(
      model, [&](const auto& p) -> Vec3<R> {
        using P = std::decay_t<decltype(p)>;
        return Saturate<R>(DeltaTransmittance<P, double>(p, glm::dvec3(wo)));
      });
}

}  // namespace clothfit
