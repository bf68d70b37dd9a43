// Model outputs as the quantities that tables hold, one place for the
// conversions f <-> rho = f |wi.z| (SPEC §1). Templated on the scalar type.
#pragma once

#include <variant>

#include "models/lafortune.h"
#include "models/math.h"
#include "models/microcylinder_cloth.h"
#include "models/microcylinder_thread.h"
#include "models/quantity.h"
#include "models/slab.h"

namespace clothfit {

using ModelParams =
    std::variant<ThreadParams, ClothParams, LafortuneModel, SlabParams>;

// Whether a model can predict a quantity (only the slab predicts
// transmittance).
inline bool ModelPredicts(const ModelParams& params, Quantity q) {
  return q == Quantity::kBrdf || q == Quantity::kCosineWeighted ||
         std::holds_alternative<SlabParams>(params);
}

// A thread alone, in the thread frame (tangent +x, normal +z).
template <typename T>
Vec3<T> ThreadValue(const ThreadParamsT<T>& p, const Vec3<T>& wi,
                    const Vec3<T>& wo, Quantity q) {
  using std::abs;
  const Vec3<T> f = ThreadBsdfLocal(p, wi, wo);
  return q == Quantity::kCosineWeighted ? f * abs(wi.z) : f;
}

// rho = f wi.z as quantity q: rho itself, or f = rho / wi.z (with wi.z
// floored at kMinCosIncidence so that f stays finite at grazing incidence).
template <typename T, typename G>
Vec3<T> FromCosineWeighted(const Vec3<T>& rho, const G& wi_z, Quantity q) {
  if (q == Quantity::kCosineWeighted) return rho;
  return rho / T(Max(wi_z, G(kMinCosIncidence)));
}

// A cloth patch in the surface frame; reflection only.
template <typename T>
Vec3<T> ClothValue(const ClothParamsT<T>& c, const Vec3<T>& wi,
                   const Vec3<T>& wo, Quantity q) {
  return FromCosineWeighted(ClothRho(c, wi, wo), wi.z, q);
}

// A slab in the surface frame: f_r or f_t (SPEC §3.4) as quantity q (rho =
// f |wi.z|), or the direct transmittance D(|wo.z|) for kTransmittance.
template <typename T, typename G>
Vec3<T> SlabValue(const SlabParamsT<T>& p, const Vec3<G>& wi, const Vec3<G>& wo,
                  Quantity q) {
  using std::abs;
  if (q == Quantity::kTransmittance) return SlabDirectTransmittance(p, wo);
  const Vec3<T> f = SlabBsdf(p, wi, wo);
  return q == Quantity::kCosineWeighted ? f * T(abs(wi.z)) : f;
}

// Double-precision evaluation of any parameter set. Requires
// ModelPredicts(params, q).
inline glm::dvec3 Evaluate(const ModelParams& params, const glm::dvec3& wi,
                           const glm::dvec3& wo, Quantity q) {
  if (const auto* p = std::get_if<ThreadParams>(&params)) {
    return ThreadValue(*p, wi, wo, q);
  }
  if (const auto* m = std::get_if<LafortuneModel>(&params)) {
    return FromCosineWeighted(LafortuneRho(*m, wi, wo), wi.z, q);
  }
  if (const auto* s = std::get_if<SlabParams>(&params)) {
    return SlabValue(*s, wi, wo, q);
  }
  return ClothValue(std::get<ClothParams>(params), wi, wo, q);
}

}  // namespace clothfit
