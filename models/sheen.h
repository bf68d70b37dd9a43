// The glTF 2.0 cloth material: the metallic-roughness base of a dielectric
// (glTF 2.0 Appendix B, metallic 0, ior 1.5) under the KHR_materials_sheen
// layer (the "Charlie" sheen of Estevez and Kulla 2017), as real-time
// renderers evaluate it for a light (three.js' MeshPhysicalMaterial, the
// Khronos sample viewer). Templated on the scalar type so that a fit
// (`clothfit fit --model sheen`, the glTF export) evaluates Jets through
// the same code. With n = +z, l = wi, v = wo, h = (l + v) / |l + v|:
//
//   D_charlie = (2 + 1/a_s) sin(theta_h)^(1/a_s) / (2 pi),  a_s = r_s^2
//               (Estevez and Kulla 2017, eq. 2; sin^2 floored at 2^-7, as
//               three.js does for half floats)
//   V_sheen   = 1 / (4 (n.l + n.v - n.l n.v))   (Neubelt and Pettineo 2013,
//               the visibility three.js uses; KHR_materials_sheen allows it)
//   f_sheen   = sheen_color D_charlie V_sheen
//   E(mu)     = min(exp(a mu + b), 1), the directional albedo of the
//               sheen lobe, a curve fit in r_s (three.js IBLSheenBRDF):
//               a = -1.9362 + 1.0678 r_s + 0.4573 r_s^2 - 0.8469 / (r_s + 0.1)
//               b = -0.6014 + 0.5538 r_s - 0.4670 r_s^2 - 0.1255 / (r_s + 0.1)
//   scaling   = 1 - max(sheen_color) max(E(n.v), E(n.l))
//               (KHR_materials_sheen, "albedo scaling")
//   F         = 0.04 + 0.96 (1 - v.h)^5                  (Schlick, ior 1.5)
//   D_ggx     = a^2 / (pi ((n.h)^2 (a^2 - 1) + 1)^2),    a = roughness^2
//   V_ggx     = 1 / (2 (n.l sqrt((n.v)^2 (1 - a^2) + a^2)
//                       + n.v sqrt((n.l)^2 (1 - a^2) + a^2)))
//   f_base    = (1 - F) base_color / pi + F D_ggx V_ggx  (fresnel_mix)
//   f         = f_sheen + scaling f_base
//
// for n.l > 0 and n.v > 0, else 0. Not modelled: three.js' multiple-
// scattering compensation of the specular lobe (a few per cent for rough
// dielectrics) and its lower bound 0.045 on the roughness plus a term from
// the screen-space normal derivatives.
#pragma once

#include <cmath>

#include "models/math.h"
#include "models/params.h"

namespace clothfit {

inline constexpr ParamInfo kSheenBaseColor = {
    "base_color",
    "unitless",
    "linear base colour of the dielectric base: its diffuse albedo "
    "(glTF baseColorFactor)",
    {0.0, 1.0},
    0.0,
    1.0,
    true,
    {0.5, 0.5, 0.5},
    "glTF 2.0, Appendix B (diffuse_brdf, baseColorFactor)",
    3};
inline constexpr ParamInfo kSheenRoughness = {
    "roughness",
    "unitless",
    "perceptual roughness of the base's specular lobe, alpha = roughness^2 "
    "(glTF roughnessFactor)",
    {0.0, 1.0, true, false},
    0.03,
    1.0,
    false,
    {0.8},
    "glTF 2.0, Appendix B (specular_brdf, roughnessFactor)",
    1};
inline constexpr ParamInfo kSheenColor = {
    "sheen_color",
    "unitless",
    "linear colour of the sheen layer (KHR_materials_sheen sheenColorFactor)",
    {0.0, 1.0},
    0.0,
    1.0,
    true,
    {0.5, 0.5, 0.5},
    "KHR_materials_sheen; Estevez and Kulla 2017",
    3};
inline constexpr ParamInfo kSheenRoughnessS = {
    "sheen_roughness",
    "unitless",
    "perceptual roughness of the sheen, alpha = sheen_roughness^2 "
    "(KHR_materials_sheen sheenRoughnessFactor)",
    {0.0, 1.0, true, false},
    0.05,
    1.0,
    false,
    {0.5},
    "KHR_materials_sheen; Estevez and Kulla 2017, eq. 2",
    1};

template <typename T>
struct SheenParamsT {
  Vec3<T> base_color = kSheenBaseColor.DefaultRgb<T>();
  T roughness = kSheenRoughness.Default<T>();
  Vec3<T> sheen_color = kSheenColor.DefaultRgb<T>();
  T sheen_roughness = kSheenRoughnessS.Default<T>();
};
using SheenParams = SheenParamsT<double>;

template <typename T, typename F>
void VisitParams(SheenParamsT<T>& p, F&& f) {
  f(kSheenBaseColor, p.base_color);
  f(kSheenRoughness, p.roughness);
  f(kSheenColor, p.sheen_color);
  f(kSheenRoughnessS, p.sheen_roughness);
}

// The Charlie distribution of the sheen microfibres at cos(theta_h).
template <typename T, typename G>
T CharlieD(const T& sheen_roughness, const G& cos_h) {
  using std::exp;
  using std::log;
  const T inv_alpha = T(1.0) / (sheen_roughness * sheen_roughness);
  const G sin2 = Max(G(1.0) - cos_h * cos_h, G(0.0078125));
  return (T(2.0) + inv_alpha) * exp(T(0.5) * inv_alpha * T(log(sin2))) *
         T(0.5 / kPi);
}

// The sheen lobe's directional albedo E(mu) (the curve fit above).
template <typename T, typename G>
T SheenAlbedo(const T& r, const G& mu) {
  using std::exp;
  const T inv = T(1.0) / (r + T(0.1));
  const T a = T(-1.9362) + T(1.0678) * r + T(0.4573) * r * r - T(0.8469) * inv;
  const T b = T(-0.6014) + T(0.5538) * r - T(0.4670) * r * r - T(0.1255) * inv;
  return Min(exp(a * T(mu) + b), T(1.0));
}

template <typename T, typename G>
Vec3<T> SheenBrdf(const SheenParamsT<T>& p, const Vec3<G>& wi,
                  const Vec3<G>& wo) {
  using std::sqrt;
  const G nl = wi.z, nv = wo.z;
  if (!(nl > G(0.0) && nv > G(0.0))) return Vec3<T>(T(0.0));
  const Vec3<G> sum = wi + wo;
  const G len = sqrt(glm::dot(sum, sum));
  const G nh = len > G(0.0) ? sum.z / len : G(1.0);
  const G vh = len > G(0.0) ? glm::dot(wo, sum) / len : G(0.0);
  // Sheen.
  const T v_sheen = T(1.0 / (4.0 * (nl + nv - nl * nv)));
  const T sheen = CharlieD(p.sheen_roughness, nh) * v_sheen;
  const T max_sheen =
      Max(Max(p.sheen_color.x, p.sheen_color.y), p.sheen_color.z);
  const T scaling =
      T(1.0) - max_sheen * Max(SheenAlbedo(p.sheen_roughness, nv),
                               SheenAlbedo(p.sheen_roughness, nl));
  // The dielectric base: fresnel_mix of the diffuse and the GGX lobe.
  const G m = G(1.0) - vh;
  const G m2 = m * m;
  const T fresnel = T(0.04 + 0.96 * m2 * m2 * m);
  const T a = p.roughness * p.roughness;
  const T a2 = a * a;
  const T d_denom = T(nh * nh) * (a2 - T(1.0)) + T(1.0);
  const T d_ggx = a2 / (T(kPi) * d_denom * d_denom);
  const T v_ggx = T(0.5) / (T(nl) * sqrt(T(nv * nv) * (T(1.0) - a2) + a2) +
                            T(nv) * sqrt(T(nl * nl) * (T(1.0) - a2) + a2));
  const T specular = fresnel * d_ggx * v_ggx;
  const T diffuse = (T(1.0) - fresnel) * T(1.0 / kPi);
  return p.sheen_color * sheen +
         (p.base_color * diffuse + Vec3<T>(specular)) * scaling;
}

template <typename T>
inline constexpr ModelInfo kModelInfo<SheenParamsT<T>> = {
    "sheen", Quantity::kBrdf, false};

template <typename T, typename G>
Vec3<T> NativeValue(const SheenParamsT<T>& p, const Vec3<G>& wi,
                    const Vec3<G>& wo) {
  return SheenBrdf(p, wi, wo);
}

}  // namespace clothfit
