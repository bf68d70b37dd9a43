// Thread BSDF of the microcylinder cloth model (Sadeghi et al. 2013, eq. 2-4;
// docs/models.md), templated on the scalar type so that the same code evaluates
// double and Ceres Jets.
//
// A thread is a locally straight cylinder with tangent t. For a direction w,
//   theta = asin(w.t)                      (longitudinal angle, [-pi/2, pi/2])
//   phi   = azimuth of w's projection on the normal plane of t,
// and theta_h = (theta_i + theta_o)/2, theta_d = (theta_i - theta_o)/2,
// phi_d = unsigned angle between the two azimuthal projections. Then
//   g(s, x) = exp(-x^2 / (2 s^2)) / (s sqrt(2 pi))
//   Fr      = dielectric Fresnel at cos = cos(theta_d) cos(phi_d / 2)
//   f_rs    = Fr cos(phi_d / 2) g(gamma_s, theta_h)                    (eq. 3)
//   f_rv    = (1 - Fr)^2 ((1 - kd) g(gamma_v, theta_h) + kd)
//             / (cos theta_i + cos theta_o) * albedo                   (eq. 4)
//   f_s     = (f_rs + f_rv) / cos^2(theta_d)                           (eq. 2)
// (1 - Fr)^2 stands for the paper's F_t(eta, wi) F_t(eta', wo').
//
// Numerics: cos(theta) is the length of w's projection on the normal plane,
// theta_h and the azimuth differences come from half-angle arctangents (see
// ComputeThreadGeometry and AngleBetween); these stay accurate and
// differentiable up to the poles, where asin/acos of a dot product lose both. A
// direction along t has no azimuth: ThreadGeometry::valid is false and the
// sample contributes nothing (docs/models.md).
#pragma once

#include <cmath>
#include <glm/geometric.hpp>
#include <memory>

#include "models/energy_bound.h"
#include "models/math.h"
#include "models/params.h"

namespace clothfit {

// Narrowest Gaussian a thread may have: far below what a measurement
// resolves, and wide enough that 1 / gamma^2 cannot overflow (gamma =
// 1e-300 degrees made the lobe inf * 0 = NaN).
inline constexpr double kThreadMinGammaDeg = 0.01;

// The parameter table of a thread (models/params.h). Defaults: Linen
// Plain (Table 2).
inline constexpr ParamInfo kThreadEta = {
    "eta",
    "unitless",
    "index of refraction of the fibres",
    {1.0, 5.0, true, false},
    1.01,
    3.0,
    false,
    {1.46},
    "Sadeghi et al. 2013, eq. 3 (Fresnel), Table 2",
    1};
inline constexpr ParamInfo kThreadKd = {
    "kd",       "unitless", "fraction of volume scattering that is isotropic",
    {0.0, 1.0}, 0.0,        1.0,
    true,       {0.3},      "Sadeghi et al. 2013, eq. 4 (k_d), Table 2",
    1};
inline constexpr ParamInfo kThreadGammaS = {
    "gamma_s_deg",
    "degrees",
    "width of the surface-reflection Gaussian (at least 0.01 degrees: "
    "its normalisation 1 / gamma stays finite)",
    {kThreadMinGammaDeg, 90.0},
    0.2,
    90.0,
    false,
    {12.0},
    "Sadeghi et al. 2013, eq. 3 (gamma_s), Table 2",
    1};
inline constexpr ParamInfo kThreadGammaV = {
    "gamma_v_deg",
    "degrees",
    "width of the volume-scattering Gaussian (at least 0.01 degrees)",
    {kThreadMinGammaDeg, 90.0},
    0.2,
    90.0,
    false,
    {24.0},
    "Sadeghi et al. 2013, eq. 4 (gamma_v), Table 2",
    1};
// Usually <= 1 (the fit's bound); a file may hold up to 1e3, which keeps
// the model finite everywhere.
inline constexpr ParamInfo kThreadAlbedo = {
    "albedo",
    "unitless",
    "volume-scattering albedo per channel",
    {0.0, 1e3},
    0.0,
    1.0,
    true,
    {0.06, 0.24, 0.3},
    "Sadeghi et al. 2013, eq. 4 (A), Table 2",
    3};

// Parameters of one thread type (the fields of the table above).
template <typename T>
struct ThreadParamsT {
  T eta = kThreadEta.Default<T>();
  T kd = kThreadKd.Default<T>();
  T gamma_s_deg = kThreadGammaS.Default<T>();
  T gamma_v_deg = kThreadGammaV.Default<T>();
  Vec3<T> albedo = kThreadAlbedo.DefaultRgb<T>();
  // kModelScale: a factor on the thread alone (a cloth's threads keep 1;
  // the cloth has its own).
  T scale = kModelScale.Default<T>();
  // The energy bound of a thread alone (models/energy_bound.h); null: the
  // paper's model as it is. A cloth's threads leave it null (the cloth has
  // its own).
  std::shared_ptr<const EnergyBound> energy_bound;
};
using ThreadParams = ThreadParamsT<double>;

template <typename T, typename F>
void VisitParams(ThreadParamsT<T>& p, F&& f) {
  f(kThreadEta, p.eta);
  f(kThreadKd, p.kd);
  f(kThreadGammaS, p.gamma_s_deg);
  f(kThreadGammaV, p.gamma_v_deg);
  f(kThreadAlbedo, p.albedo);
}

// Entries of the flat layout (models/params.h ToArray).
inline constexpr int kThreadFlatSize = 7;

// Unit-area Gaussian of width s (radians), docs/models.md g(s, x), with
// its constants computed once: a thread's lobes evaluate it at every
// tangent sample.
template <typename T>
struct Gaussian {
  T inv_two_var;  // 1 / (2 s^2)
  T peak;         // 1 / (s sqrt(2 pi))

  explicit Gaussian(const T& s)
      : inv_two_var(T(1.0) / (T(2.0) * s * s)),
        peak(T(1.0) / (s * T(std::sqrt(2.0 * kPi)))) {}
  template <typename X>
  T operator()(const X& x) const {
    return peak * ExpNeg(T(x * x) * inv_two_var);
  }
};

// Unpolarised Fresnel reflectance of a dielectric of relative index eta > 1
// for cos_theta in [0, 1] (Cook and Torrance 1982, the exact form), given
// eta^2 - 1.
template <typename T, typename C>
T FresnelDielectricGiven(const C& cos_theta, const T& eta2_minus_1) {
  using std::sqrt;
  const T c(Clamp(cos_theta, C(0.0), C(1.0)));
  const T g = sqrt(eta2_minus_1 + c * c);
  const T a = T(0.5) * Sqr(g - c) / Sqr(g + c);
  const T b = T(1.0) + Sqr(c * (g + c) - T(1.0)) / Sqr(c * (g - c) + T(1.0));
  return a * b;
}

// Angles of a (wi, wo) pair relative to one thread (tangent t, local normal
// n perpendicular to t, and b = t x n).
template <typename T>
struct ThreadGeometry {
  bool valid = false;  // theta/phi defined (azimuthal projections > 0)
  T sin_theta_i, sin_theta_o;
  T cos_theta_i, cos_theta_o;
  T theta_h;               // (theta_i + theta_o) / 2
  T cos2_theta_d;          // cos^2((theta_i - theta_o) / 2)
  T cos_half_phi_d;        // cos(phi_d / 2)
  T cos_phi_i, cos_phi_o;  // azimuthal projections against n
  // phi_d in [0, pi]. It enters only the cloth's masking term M, which
  // vanishes unless both cos phi are positive; elsewhere it is left at 0
  // to spare an arctangent.
  T phi_d = T(0.0);
};

// Projections shorter than this (squared) count as zero length.
inline constexpr double kMinProjectionLength2 = 1e-24;

// The azimuths of wi and wo about a thread: unit vectors (cos phi, sin phi)
// in the normal plane of t, in its basis (n, b).
template <typename T>
struct ThreadAzimuths {
  Vec2<T> i, o;
};

// The steps of ComputeThreadGeometry, so that a cloth's tangent sample
// (models/microcylinder_cloth.h) takes only those its masking terms leave
// non-zero; each sets the fields its comment names.

// The projections of wi and wo on the normal plane of t: sin/cos theta,
// cos phi against n, and `valid`; `azimuths` receives their directions.
// The projection of w has coordinates (w.n, w.b) in the basis (n, b), so
// cos^2 theta = (w.n)^2 + (w.b)^2, free of the cancellation of
// |w - (w.t) t| near t. wi_b = wi.b and wo_b = wo.b are given: the tangent
// samples of a cloth's thread share b. False (valid stays false) where a
// projection has no azimuth.
template <typename T>
bool ProjectOnThread(const Vec3<T>& t, const Vec3<T>& n, const T& wi_b,
                     const T& wo_b, const Vec3<T>& wi, const Vec3<T>& wo,
                     ThreadGeometry<T>* g, ThreadAzimuths<T>* azimuths) {
  using std::sqrt;
  g->sin_theta_i = glm::dot(wi, t);
  g->sin_theta_o = glm::dot(wo, t);
  const T wi_n = glm::dot(wi, n), wo_n = glm::dot(wo, n);
  const T pi2 = wi_n * wi_n + wi_b * wi_b;
  const T po2 = wo_n * wo_n + wo_b * wo_b;
  const T kMin(kMinProjectionLength2);
  if (!(pi2 > kMin && po2 > kMin)) return false;
  g->valid = true;
  g->cos_theta_i = sqrt(pi2);
  g->cos_theta_o = sqrt(po2);
  const T inv_i = T(1.0) / g->cos_theta_i, inv_o = T(1.0) / g->cos_theta_o;
  g->cos_phi_i = wi_n * inv_i;
  g->cos_phi_o = wo_n * inv_o;
  azimuths->i = Vec2<T>(g->cos_phi_i, wi_b * inv_i);
  azimuths->o = Vec2<T>(g->cos_phi_o, wo_b * inv_o);
  return true;
}

// phi_d from the azimuths, where both cos phi are positive (elsewhere the
// masking term it enters vanishes and it stays 0).
template <typename T>
void ThreadAzimuthDifference(const ThreadAzimuths<T>& a, ThreadGeometry<T>* g) {
  if (g->cos_phi_i > T(0.0) && g->cos_phi_o > T(0.0)) {
    g->phi_d = AngleBetween(a.i, a.o, T(1.0));
  }
}

// theta_h, cos^2(theta_d) and cos(phi_d / 2): what the lobes read.
// Half-angle identities spare three of the four trigonometric calls:
//   theta_h = atan(sin(theta_i + theta_o) / (1 + cos(theta_i + theta_o)))
//   cos^2(theta_d) = (1 + cos(theta_i - theta_o)) / 2
//   cos(phi_d / 2) = |unit pi + unit po| / 2.
// theta_i + theta_o lies in (-pi, pi) for valid geometry, so the first
// denominator is positive.
template <typename T>
void ThreadHalfAngles(const ThreadAzimuths<T>& a, ThreadGeometry<T>* g) {
  using std::atan;
  const T cos_sum =
      g->cos_theta_i * g->cos_theta_o - g->sin_theta_i * g->sin_theta_o;
  const T sin_sum =
      g->sin_theta_i * g->cos_theta_o + g->cos_theta_i * g->sin_theta_o;
  const T cos_diff =
      g->cos_theta_i * g->cos_theta_o + g->sin_theta_i * g->sin_theta_o;
  g->theta_h = atan(sin_sum / (T(1.0) + cos_sum));
  g->cos2_theta_d = Max(T(0.5) * (T(1.0) + cos_diff), T(0.0));
  // cos(phi_d / 2) = |unit pi + unit po| / 2: free of the cancellation of
  // 1 + cos(phi_d) at opposite azimuths (in float, sqrt((1 + cos phi_d) /
  // 2) lost two digits at 89.9 degrees).
  const Vec2<T> half = a.i + a.o;
  g->cos_half_phi_d = Min(T(0.5) * SafeSqrt(glm::dot(half, half)), T(1.0));
}

// Every field of the geometry (where valid).
template <typename T>
ThreadGeometry<T> ComputeThreadGeometry(const Vec3<T>& t, const Vec3<T>& n,
                                        const Vec3<T>& wi, const Vec3<T>& wo) {
  ThreadGeometry<T> g;
  const Vec3<T> b = glm::cross(t, n);
  ThreadAzimuths<T> azimuths;
  if (!ProjectOnThread(t, n, T(glm::dot(wi, b)), T(glm::dot(wo, b)), wi, wo, &g,
                       &azimuths)) {
    return g;
  }
  ThreadHalfAngles(azimuths, &g);
  ThreadAzimuthDifference(azimuths, &g);
  return g;
}

// What the lobes of eq. 3-4 take from a thread's parameters alone,
// computed once per thread and evaluation (not per tangent sample).
template <typename T>
struct ThreadLobeParams {
  explicit ThreadLobeParams(const ThreadParamsT<T>& p)
      : eta2_minus_1(p.eta * p.eta - T(1.0)),
        kd(p.kd),
        one_minus_kd(T(1.0) - p.kd),
        surface(Radians(p.gamma_s_deg)),
        volume(Radians(p.gamma_v_deg)) {}
  T eta2_minus_1;
  T kd, one_minus_kd;
  Gaussian<T> surface, volume;  // g(gamma_s, .), g(gamma_v, .)
};

// The Fresnel reflectance of eq. 3 for a valid geometry: the dielectric
// Fresnel at cos = cos(theta_d) cos(phi_d / 2).
template <typename T, typename G>
T ThreadFresnel(const ThreadGeometry<G>& g, const ThreadLobeParams<T>& lp) {
  using std::sqrt;
  return FresnelDielectricGiven(G(sqrt(g.cos2_theta_d) * g.cos_half_phi_d),
                                lp.eta2_minus_1);
}

// The two lobes of the thread BSDF for a valid geometry, f_s = surface +
// volume * albedo per channel (eq. 2-4, already divided by cos^2(theta_d)),
// given the Fresnel reflectance fr = ThreadFresnel(g, lp). Kept apart so
// that sums over tangent samples stay scalar until the albedo is applied.
// The geometry's scalar type G and fr's type F may differ from the
// parameters' T: a fit with fixed directions (and fixed eta) computes them
// once in double and evaluates only the parameter-dependent part with Jets.
template <typename T>
struct ThreadLobes {
  T surface;  // f_rs / cos^2(theta_d)
  T volume;   // f_rv / (albedo cos^2(theta_d))
};

template <typename T, typename G, typename F>
ThreadLobes<T> ThreadLobesGivenFresnel(const ThreadGeometry<G>& g, const F& fr,
                                       const ThreadLobeParams<T>& lp) {
  const G inv_cos2 = G(1.0) / g.cos2_theta_d;
  ThreadLobes<T> lobes;
  lobes.surface = T(fr * g.cos_half_phi_d * inv_cos2) * lp.surface(g.theta_h);
  lobes.volume =
      T(Sqr(F(1.0) - fr) * inv_cos2 / (g.cos_theta_i + g.cos_theta_o)) *
      (lp.one_minus_kd * lp.volume(g.theta_h) + lp.kd);
  return lobes;
}

template <typename T, typename G>
ThreadLobes<T> ThreadLobesOf(const ThreadGeometry<G>& g,
                             const ThreadLobeParams<T>& lp) {
  return ThreadLobesGivenFresnel(g, ThreadFresnel(g, lp), lp);
}

// Thread BSDF f_s (1/sr) per channel for a valid geometry (eq. 2-4).
template <typename T, typename G>
Vec3<T> ThreadBsdf(const ThreadGeometry<G>& g, const ThreadParamsT<T>& p) {
  const ThreadLobes<T> lobes = ThreadLobesOf(g, ThreadLobeParams<T>(p));
  return Vec3<T>(lobes.surface) + p.albedo * lobes.volume;
}

// The thread BSDF in the thread frame of docs/formats.md (tangent +x, normal
// +z): what a thread table measures. Zero where the geometry is undefined.
template <typename T>
Vec3<T> ThreadBsdfLocal(const ThreadParamsT<T>& p, const Vec3<T>& wi,
                        const Vec3<T>& wo) {
  const Vec3<T> t(T(1.0), T(0.0), T(0.0));
  const Vec3<T> n(T(0.0), T(0.0), T(1.0));
  const ThreadGeometry<T> g = ComputeThreadGeometry(t, n, wi, wo);
  if (!g.valid) return Vec3<T>(T(0.0));
  return ThreadBsdf(g, p);
}

template <typename T>
inline constexpr ModelInfo kModelInfo<ThreadParamsT<T>> = {
    "thread", Quantity::kBrdf, false};

// A thread alone, in the thread frame: its BSDF f (eq. 2) times the
// model's scale, bounded by its energy bound.
template <typename T, typename G>
Vec3<T> NativeValue(const ThreadParamsT<T>& p, const Vec3<G>& wi,
                    const Vec3<G>& wo) {
  return ThreadBsdfLocal(p, Cast<T>(wi), Cast<T>(wo)) *
         (p.scale * T(EnergyBoundFactor(p.energy_bound.get(), wi.z, wo.z)));
}

}  // namespace clothfit
