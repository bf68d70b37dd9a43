// Optically thin semi-transparent slab (Frisvad et al., "Rendering thin
// semi-transparent objects", after Chandrasekhar 1960; docs/models.md),
// templated on the scalar type so that the same code evaluates double and Ceres
// Jets.
//
// A plane-parallel layer of optical thickness tau with isotropic scattering
// (phase function A / (4 pi), single-scattering albedo A), lit by a
// collimated beam. With mu_i = |wi.z|, mu_o = |wo.z| and optical depth t
// measured from the lit face, a photon of the beam reaches depth t with
// probability exp(-t / mu_i), scatters once into mu_o with density
// A / (4 pi) per unit optical path, and leaves through the lit face with
// exp(-t / mu_o) or through the far face with exp(-(tau - t) / mu_o).
// Per unit irradiance on the face (1/sr), integrating over t in [0, tau]:
//
//   D(mu)    = exp(-tau / mu)                               direct, (alpha = 1
//   - D) f_r      = A/(4 pi) (1 - exp(-tau (1/mu_i + 1/mu_o))) / (mu_i + mu_o)
//   f_t      = A/(4 pi) (exp(-tau/mu_o) - exp(-tau/mu_i)) / (mu_o - mu_i)
//
// (the paper's eq. 4-5 and 7-8 for radiance, divided by the irradiance
// mu_i F). Both are symmetric in mu_i, mu_o (reciprocity); f_r tends to
// the Lommel-Seeliger law A/(4 pi)/(mu_i + mu_o) as tau -> infinity.
//
// Numerics. f_t is a divided difference of exp(-tau/mu), with a removable
// singularity at mu_o = mu_i. With M = max(mu_i, mu_o), m = min(mu_i, mu_o)
// and y = tau (1/m - 1/M) >= 0,
//
//   f_t = A/(4 pi) exp(-tau/M) (1 - exp(-y)) / (M - m)              (a)
//       = A/(4 pi) tau / (M m) exp(-tau/M) E(y),  E(y) = (1 - e^-y)/y  (b)
//
// E(y) = int_0^1 exp(-s y) ds is the mean attenuation, smooth with E(0) = 1.
// Form (a) is the paper's; its value and derivatives cancel as y -> 0. Form
// (b) is exact everywhere; near y = 0 (|y| < kSlabSeriesSwitch, a band
// around mu_o = mu_i whose width grows with mu^2 / tau) E comes from its
// Taylor series E(y) = sum_k (-y)^k / (k+1)!, truncated after
// kSlabSeriesTerms terms (remainder < 0.25^14 / 15! < 1e-20), so value and
// all derivatives are smooth through mu_o = mu_i; outside the band form (a)
// is used. Where the two meet, the closed form's relative error in E is
// about eps, and in E' about 2 eps / y = 2e-15: the branches agree to better
// than 1e-12 in value and first derivatives (tests/slab_model_test.cc).
// 1 - exp(-x) is always computed as -expm1(-x) (no cancellation for small
// tau).
//
// Grazing: as mu_o -> 0 (or mu_i -> 0), exp(-tau/mu) -> 0 with all its
// derivatives, so D -> 0, f_r -> A/(4 pi)/(mu_i + mu_o) and f_t -> A/(4 pi)
// exp(-tau/M)/M. Below kSlabMinMu the code returns these limits exactly
// (no 0 * Inf in Jets). Only f_r with both directions grazing diverges
// (like Lommel-Seeliger); mu_i + mu_o is floored at kSlabMinMuSum there.
#pragma once

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include "models/math.h"
#include "models/params.h"

namespace clothfit {

// Below this |w.z| a direction counts as exactly grazing (see above).
inline constexpr double kSlabMinMu = 1e-150;
// Series branch of the mean attenuation E(y) for y below this.
inline constexpr double kSlabSeriesSwitch = 0.25;
inline constexpr int kSlabSeriesTerms = 14;
// Its coefficients 1 / (k + 1)!, k = 0 .. 13.
inline constexpr double kSlabSeries[kSlabSeriesTerms] = {1.0,
                                                         1.0 / 2,
                                                         1.0 / 6,
                                                         1.0 / 24,
                                                         1.0 / 120,
                                                         1.0 / 720,
                                                         1.0 / 5040,
                                                         1.0 / 40320,
                                                         1.0 / 362880,
                                                         1.0 / 3628800,
                                                         1.0 / 39916800,
                                                         1.0 / 479001600,
                                                         1.0 / 6227020800.0,
                                                         1.0 / 87178291200.0};
// f_r diverges when both directions are grazing; mu_i + mu_o is floored
// here (the cloth model's kMinCosIncidence, a choice of ours;
// docs/decisions.md).
inline constexpr double kSlabMinMuSum = 1e-7;
// Documented range of tau (the model is meant for tau well below 1; the
// upper limit only keeps numbers finite).
inline constexpr double kSlabMinTau = 1e-12;
inline constexpr double kSlabMaxTau = 1e4;
// The paper's bound: the single-scattering approximation "differs less than
// 1 per cent" for tau below this (Frisvad et al. Sec. 3, citing
// Chandrasekhar 1960, p. 205). Our Monte Carlo disagrees for f_r, f_t at
// all but low albedo (SlabSingleScatterError below, docs/slab.md).
inline constexpr double kSlabPaperTauLimit = 0.2;
// The accuracy the paper promises; a larger estimated error is reported
// as outside the model's regime.
inline constexpr double kSlabRegimeTolerance = 0.01;

// The parameter table (models/params.h). Defaults: a thin, bright curtain
// (tau = 0.1, well inside the single-scattering regime; A = 1 as in the
// paper's Fig. 2). A fit searches tau in [1e-6, 100]: beyond, the data
// cannot tell tau apart (the slab is clear or opaque).
inline constexpr ParamInfo kSlabTau = {
    "tau",
    "unitless",
    "optical thickness: the extinction coefficient integrated across the "
    "slab (a scalar in files sets all three channels)",
    {kSlabMinTau, kSlabMaxTau},
    1e-6,
    100.0,
    false,
    {0.1, 0.1, 0.1},
    "Frisvad et al., Sec. 3 (tau_1); docs/models.md",
    3};
inline constexpr ParamInfo kSlabAlbedo = {
    "albedo",
    "unitless",
    "single-scattering albedo sigma_s / sigma_t (phase function A / (4 pi))",
    {0.0, 1.0},
    0.0,
    1.0,
    true,
    {1.0, 1.0, 1.0},
    "Frisvad et al., Sec. 3 (A)",
    3};

template <typename T>
struct SlabParamsT {
  Vec3<T> tau = kSlabTau.DefaultRgb<T>();
  Vec3<T> albedo = kSlabAlbedo.DefaultRgb<T>();
};
using SlabParams = SlabParamsT<double>;

template <typename T, typename F>
void VisitParams(SlabParamsT<T>& p, F&& f) {
  f(kSlabTau, p.tau);
  f(kSlabAlbedo, p.albedo);
}

// Whether the three channels share one tau (written as a scalar).
inline bool SlabTauIsScalar(const SlabParams& p) {
  return p.tau.x == p.tau.y && p.tau.x == p.tau.z;
}

// E(y) = (1 - exp(-y)) / y by its Taylor series (for 0 <= y < 0.25).
template <typename T>
T MeanAttenuationSeries(const T& y) {
  // Horner in z = -y from the last term.
  const T z = -y;
  T sum(kSlabSeries[kSlabSeriesTerms - 1]);
  for (int k = kSlabSeriesTerms - 2; k >= 0; --k) {
    sum = sum * z + T(kSlabSeries[k]);
  }
  return sum;
}

// E(y) = (1 - exp(-y)) / y in closed form (for y > 0).
template <typename T>
T MeanAttenuationClosed(const T& y) {
  using std::expm1;
  return -expm1(-y) / y;
}

// E(y) = (1 - exp(-y)) / y = int_0^1 exp(-s y) ds for y >= 0, smooth at 0.
template <typename T>
T MeanAttenuation(const T& y) {
  return y < T(kSlabSeriesSwitch) ? MeanAttenuationSeries(y)
                                  : MeanAttenuationClosed(y);
}

// Direct transmittance D(mu) = exp(-tau / mu) along a direction with
// |w.z| = mu (Frisvad et al. eq. 7-9); 0 at grazing.
template <typename T>
T DirectTransmittance(const T& tau, const T& mu) {
  using std::exp;
  if (!(mu > T(kSlabMinMu))) return T(0.0) * tau;
  return exp(-tau / mu);
}

// f_r / (A / (4 pi)) for one channel: (1 - exp(-tau (1/mu_i + 1/mu_o))) /
// (mu_i + mu_o).
template <typename T>
T SlabReflectionFactor(const T& tau, const T& mu_i, const T& mu_o) {
  using std::expm1;
  const T sum = mu_i + mu_o;
  const T lo = Min(mu_i, mu_o);
  if (!(lo > T(kSlabMinMu))) {  // exp(-tau (...)) = 0: the grazing limit
    return T(1.0) / Max(sum, T(kSlabMinMuSum)) + T(0.0) * tau;
  }
  return -expm1(-tau * sum / (mu_i * mu_o)) / sum;
}

// f_t / (A / (4 pi)) for one channel: the divided difference of
// exp(-tau/mu) between mu_i and mu_o, by form (a) or (b) above.
template <typename T>
T SlabTransmissionFactor(const T& tau, const T& mu_i, const T& mu_o) {
  using std::exp;
  using std::expm1;
  // One comparison, so that at mu_i = mu_o each keeps its own derivative.
  const bool swap = mu_o > mu_i;
  const T& hi = swap ? mu_o : mu_i;
  const T& lo = swap ? mu_i : mu_o;
  if (!(hi > T(kSlabMinMu))) return T(0.0) * tau;  // both grazing: 0
  const T outer = exp(-tau / hi);
  if (!(lo > T(kSlabMinMu))) return outer / hi;  // exp(-tau/lo) = 0
  const T y = tau * (hi - lo) / (hi * lo);
  if (y < T(kSlabSeriesSwitch)) {
    return tau / (hi * lo) * outer * MeanAttenuationSeries(y);  // (b)
  }
  return outer * -expm1(-y) / (hi - lo);  // (a)
}

// Reflection f_r per channel (1/sr), light and viewer on the same side.
template <typename T>
Vec3<T> SlabReflection(const SlabParamsT<T>& p, const T& mu_i, const T& mu_o) {
  Vec3<T> f;
  for (int c = 0; c < 3; ++c) {
    f[c] = p.albedo[c] * T(1.0 / (4.0 * kPi)) *
           SlabReflectionFactor(p.tau[c], mu_i, mu_o);
  }
  return f;
}

// Diffuse transmission f_t per channel (1/sr), viewer on the far side.
template <typename T>
Vec3<T> SlabTransmission(const SlabParamsT<T>& p, const T& mu_i,
                         const T& mu_o) {
  Vec3<T> f;
  for (int c = 0; c < 3; ++c) {
    f[c] = p.albedo[c] * T(1.0 / (4.0 * kPi)) *
           SlabTransmissionFactor(p.tau[c], mu_i, mu_o);
  }
  return f;
}

// D per channel along a direction w.
template <typename T, typename G>
Vec3<T> SlabDirectTransmittance(const SlabParamsT<T>& p, const Vec3<G>& w) {
  using std::abs;
  const T mu(abs(w.z));
  return Vec3<T>(DirectTransmittance(p.tau.x, mu),
                 DirectTransmittance(p.tau.y, mu),
                 DirectTransmittance(p.tau.z, mu));
}

template <typename T>
inline constexpr ModelInfo kModelInfo<SlabParamsT<T>> = {"slab",
                                                         Quantity::kBrdf, true};

// Whether wo lies on the far side of the slab from wi (transmission).
template <typename G>
bool SlabTransmits(const Vec3<G>& wi, const Vec3<G>& wo) {
  return wi.z * wo.z < G(0.0);
}

// The scattered BSDF f (1/sr) for a direction pair in the surface frame:
// f_r when wo is on the side of wi, f_t when it is on the far side. The
// slab is symmetric, so light from below (wi.z < 0) works alike.
template <typename T, typename G>
Vec3<T> SlabBsdf(const SlabParamsT<T>& p, const Vec3<G>& wi,
                 const Vec3<G>& wo) {
  using std::abs;
  const T mu_i(abs(wi.z));
  const T mu_o(abs(wo.z));
  return SlabTransmits(wi, wo) ? SlabTransmission(p, mu_i, mu_o)
                               : SlabReflection(p, mu_i, mu_o);
}

template <typename T, typename G>
Vec3<T> NativeValue(const SlabParamsT<T>& p, const Vec3<G>& wi,
                    const Vec3<G>& wo) {
  return SlabBsdf(p, wi, wo);
}

template <typename T, typename G>
Vec3<T> Transmittance(const SlabParamsT<T>& p, const Vec3<G>& wo) {
  return SlabDirectTransmittance(p, wo);
}

// How wrong single scattering is, for double only (not part of the fitted
// model). Light scattered once at a depth t that is uniform in [0, tau]
// (the first-collision density of a thin slab) and sent out isotropically
// meets the slab again with probability
//   q(tau) = 1 - (1/tau) int_0^tau E2(t) dt = 1 - (1/2 - E3(tau)) / tau
//          = (tau/2) (ln(1/tau) + 3/2 - gamma) + sum_{k>=3} (-1)^(k+1)
//            tau^(k-1) / ((k-2) k!),
// (E_n: exponential integrals; the series from A&S 5.1.12). It grows like
// tau ln(1/tau): paths near grazing stay long in a thin layer. Each further
// order adds a factor A q, so all orders are ~ single / (1 - A q), and the
// single-scattering f_r, f_t are low by the fraction A q(tau). Against the
// Monte Carlo chart (docs/slab.md) this estimate is within 0.001 (absolute)
// for tau <= 0.2 and within 0.02 for tau <= 1; it overestimates for
// thicker slabs.
inline double SlabRescatterProbability(double tau) {
  constexpr double kEulerGamma = 0.57721566490153286;
  if (tau <= 2.0) {
    double sum = 0.5 * tau * (-std::log(tau) + 1.5 - kEulerGamma);
    double power = tau * tau;  // tau^(k-1)
    double factorial = 6.0;    // k!
    for (int k = 3; k < 40; ++k) {
      sum += (k % 2 == 1 ? 1.0 : -1.0) * power / ((k - 2) * factorial);
      power *= tau;
      factorial *= k + 1;
    }
    return sum;
  }
  // E1 by its continued fraction (modified Lentz), then E2, E3 upwards.
  double b = tau + 1.0, c = 1e300, d = 1.0 / b, h = d;
  for (int i = 1; i < 200; ++i) {
    const double an = -static_cast<double>(i) * i;
    b += 2.0;
    d = 1.0 / (an * d + b);
    c = b + an / c;
    const double delta = c * d;
    h *= delta;
    if (std::abs(delta - 1.0) < 1e-16) break;
  }
  const double e1 = h * std::exp(-tau);
  const double e2 = std::exp(-tau) - tau * e1;
  const double e3 = 0.5 * (std::exp(-tau) - tau * e2);
  return 1.0 - (0.5 - e3) / tau;
}

// The estimated relative error A q(tau) of the single-scattering f_r, f_t
// against all orders of scattering (thin-slab estimate, see above).
inline double SlabSingleScatterError(double tau, double albedo) {
  return albedo * SlabRescatterProbability(tau);
}

// The estimated relative error of the single-scattering f_r, f_t for a
// parameter set: the largest SlabSingleScatterError over the channels.
// Above kSlabRegimeTolerance the parameters lie outside the model's regime
// (docs/models.md: "where it is not [accurate], the tool says so";
// docs/slab.md).
inline double SlabParamsSingleScatterError(const SlabParams& p) {
  double error = 0.0;
  for (int c = 0; c < 3; ++c) {
    error = std::max(error, SlabSingleScatterError(p.tau[c], p.albedo[c]));
  }
  return error;
}

// The albedo whose all-orders slab matches a single-scattering fit's albedo
// A_fit: A_fit ~ A / (1 - A q)  =>  A = A_fit / (1 + A_fit q).
inline double SlabMultipleScatteringAlbedo(double tau, double fitted_albedo) {
  return fitted_albedo / (1.0 + fitted_albedo * SlabRescatterProbability(tau));
}

}  // namespace clothfit
