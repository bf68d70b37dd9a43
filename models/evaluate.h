// Every model behind one interface: the variant ModelParams of their
// parameter sets, and their values as the quantities tables hold. The one
// place that converts between the BSDF f and rho = f |wi.z| (docs/formats.md):
// each model evaluates the quantity its paper defines (NativeValue and
// kModelInfo in its header), and Value converts. Templated on the scalar
// type, so that a fit evaluates Jets through the same code.
#pragma once

#include <cmath>
#include <string>
#include <variant>

#include "models/holes_tile.h"
#include "models/lafortune.h"
#include "models/math.h"
#include "models/microcylinder_cloth.h"
#include "models/microcylinder_thread.h"
#include "models/quantity.h"
#include "models/sheen.h"
#include "models/slab.h"

namespace clothfit {

using ModelParams = std::variant<ThreadParams, ClothParams, LafortuneModel,
                                 SlabParams, HolesModel, SheenParams>;

// Smallest wi.z used to turn rho into the BRDF f = rho / wi.z, so that f
// stays finite at exactly grazing incidence.
inline constexpr double kMinCosIncidence = 1e-7;

// A value of quantity `from` (kBrdf or kCosineWeighted) as quantity `to`:
// rho = f |wi.z|, f = rho / max(wi.z, kMinCosIncidence).
template <typename T, typename G>
Vec3<T> ConvertQuantity(const Vec3<T>& value, Quantity from, Quantity to,
                        const G& wi_z) {
  using std::abs;
  if (from == to) return value;
  if (to == Quantity::kCosineWeighted) return value * T(abs(wi_z));
  return value * (T(1.0) / T(Max(wi_z, G(kMinCosIncidence))));  // one division
}

// The factor k of ConvertQuantity, value_to = k value_from (also the
// factor of a sigma): |wi.z| from f to rho, 1 / max(wi.z,
// kMinCosIncidence) from rho to f, 1 for the same quantity.
inline double QuantityFactor(Quantity from, Quantity to, double wi_z) {
  if (from == to) return 1.0;
  if (to == Quantity::kCosineWeighted) return std::abs(wi_z);
  return 1.0 / Max(wi_z, kMinCosIncidence);
}

// The factor that turns a value of quantity `from` into rho.
inline double CosineWeightedFactor(Quantity from, double wi_z) {
  return QuantityFactor(from, Quantity::kCosineWeighted, wi_z);
}

// Whether parameters of type P predict quantity q.
template <typename P>
bool Predicts(Quantity q) {
  constexpr ModelInfo info = kModelInfo<P>;
  if (q == Quantity::kTransmittance) return info.transmittance;
  return info.native != Quantity::kTransmittance;
}

// The value of parameters p (any model's, any scalar type) at (wi, wo) as
// quantity q; zero where the model does not predict q (Predicts).
template <typename P, typename G>
auto Value(const P& p, const Vec3<G>& wi, const Vec3<G>& wo, Quantity q) {
  constexpr ModelInfo info = kModelInfo<P>;
  static_assert(info.name != nullptr, "P is not a model's parameter type");
  using V = decltype(NativeValue(p, wi, wo));
  using T = typename V::value_type;
  if (!Predicts<P>(q)) return V(T(0.0));
  if constexpr (info.transmittance) {
    if (q == Quantity::kTransmittance) return V(Transmittance(p, wo));
  }
  return ConvertQuantity(NativeValue(p, wi, wo), info.native, q, wi.z);
}

// The cosine-weighted BRDF rho = f |wi.z| and the BRDF f of any model that
// predicts them.
template <typename P, typename G>
auto Rho(const P& p, const Vec3<G>& wi, const Vec3<G>& wo) {
  return Value(p, wi, wo, Quantity::kCosineWeighted);
}
template <typename P, typename G>
auto Brdf(const P& p, const Vec3<G>& wi, const Vec3<G>& wo) {
  return Value(p, wi, wo, Quantity::kBrdf);
}

inline bool ModelPredicts(const ModelParams& params, Quantity q) {
  return std::visit(
      [&](const auto& p) { return Predicts<std::decay_t<decltype(p)>>(q); },
      params);
}

// "thread" | "cloth" | "lafortune" | "slab" | "holes" | "sheen".
inline const char* ModelName(const ModelParams& params) {
  return std::visit(
      [](const auto& p) { return kModelInfo<std::decay_t<decltype(p)>>.name; },
      params);
}

// Double-precision evaluation of any parameter set; zero where the model
// does not predict q.
inline glm::dvec3 Evaluate(const ModelParams& params, const glm::dvec3& wi,
                           const glm::dvec3& wo, Quantity q) {
  return std::visit(
      [&](const auto& p) -> glm::dvec3 { return Value(p, wi, wo, q); }, params);
}

// The ranges of every model's parameter table (models/params.h) and the
// model's own rules: "" when valid, else a message naming the entry.
inline std::string ValidateModel(const ModelParams& params) {
  if (const auto* p = std::get_if<ThreadParams>(&params)) {
    const std::string e = ValidateParams(*p);
    return e.empty() ? CheckParam(kModelScale, p->scale) : e;
  }
  if (const auto* c = std::get_if<ClothParams>(&params)) {
    return ValidateClothParams(*c);
  }
  if (const auto* m = std::get_if<LafortuneModel>(&params)) {
    const std::string e = ValidateLafortuneParams(m->params);
    return e.empty() ? ValidateViewTable(m->lut) : e;
  }
  if (const auto* s = std::get_if<SlabParams>(&params)) {
    return ValidateParams(*s);
  }
  if (const auto* s = std::get_if<SheenParams>(&params)) {
    return ValidateParams(*s);
  }
  const HolesModel& h = std::get<HolesModel>(params);
  if (!h.tile) return "a holes model needs its mask";
  const std::string e = ValidateParams(h.params);
  return e.empty() ? ValidateHolesTile(*h.tile) : e;
}

}  // namespace clothfit
