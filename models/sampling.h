// Building blocks of importance sampling for path tracers (the models'
// samplers: models/cloth_sampling.h, models/model_sampling.h), templated
// on the scalar type R (float or double). Densities are per steradian.
//
// - the cosine-weighted hemisphere about +z, pdf z / pi (Malley's method);
// - a cosine-power (Phong) lobe about a unit axis a, pdf (N + 1) / (2 pi)
//   max(w.a, 0)^N (Lafortune and Willems 1994);
// - the longitudinal cone of a thread's specular lobe (truncated logistic in
//   theta = asin(w.t) about the axis t, uniform azimuth);
// - reflection about a GGX visible normal (the glTF base's specular lobe);
// - mirroring through the surface plane: a density p on the whole sphere,
//   sampled and then mirrored (w.z -> -w.z when w.z < 0), has the density
//   p(w) + p(mirror(w)) on the upper hemisphere. So no sample is lost below
//   the surface, and the density stays exact.
// - choosing a mixture's component with one uniform number and reusing the
//   rest of its precision for the chosen component.
#pragma once

#include <cmath>

#include "models/math.h"

namespace clothfit {

// A direction and its density (per steradian). `delta`: a direction that
// carries a finite amount of light (direct transmission, wi = -wo); `pdf`
// is then the probability of choosing it, not a density.
template <typename R>
struct DirectionSample {
  Vec3<R> wi = Vec3<R>(R(0.0), R(0.0), R(1.0));
  R pdf = R(0.0);
  bool delta = false;
};

// The largest R below 1, so that a remapped uniform number stays in [0, 1).
template <typename R>
constexpr R kOneBelow = R(1.0) - R(sizeof(R) == sizeof(float) ? 6e-8 : 1.2e-16);

// Mixture components: picks the first k with u < w_0 + ... + w_k of the
// weights w (summing to 1; the last positive one if rounding leaves u
// beyond them) and rescales u into [0, 1) within w_k.
template <typename R>
int PickComponent(const R* weights, int count, R* u) {
  R start = R(0.0);
  int chosen = -1;
  R chosen_start = R(0.0);
  for (int k = 0; k < count; ++k) {
    if (!(weights[k] > R(0.0))) continue;
    chosen = k;
    chosen_start = start;
    if (*u < start + weights[k]) break;
    start += weights[k];
  }
  if (chosen < 0) return -1;
  *u = Clamp((*u - chosen_start) / weights[chosen], R(0.0), kOneBelow<R>);
  return chosen;
}

// An orthonormal frame (e1, e2) of the plane perpendicular to the unit
// vector a (Duff et al. 2017, "Building an orthonormal basis, revisited").
template <typename R>
void PerpendicularFrame(const Vec3<R>& a, Vec3<R>* e1, Vec3<R>* e2) {
  const R sign = a.z >= R(0.0) ? R(1.0) : R(-1.0);
  const R p = R(-1.0) / (sign + a.z);
  const R q = a.x * a.y * p;
  *e1 = Vec3<R>(R(1.0) + sign * a.x * a.x * p, sign * q, -sign * a.x);
  *e2 = Vec3<R>(q, sign + a.y * a.y * p, -a.y);
}

// The direction at polar cosine c and azimuth phi about the unit axis a.
template <typename R>
Vec3<R> AboutAxis(const Vec3<R>& a, const R& cos_theta, const R& phi) {
  using std::cos;
  using std::sin;
  using std::sqrt;
  Vec3<R> e1, e2;
  PerpendicularFrame(a, &e1, &e2);
  const R sin_theta = sqrt(Max(R(1.0) - cos_theta * cos_theta, R(0.0)));
  return a * cos_theta + (e1 * cos(phi) + e2 * sin(phi)) * sin_theta;
}

template <typename R>
Vec3<R> SampleCosineHemisphere(const R& u1, const R& u2) {
  return AboutAxis(Vec3<R>(R(0.0), R(0.0), R(1.0)),
                   std::sqrt(Max(R(1.0) - u1, R(0.0))), R(2.0 * kPi) * u2);
}

template <typename R>
R CosineHemispherePdf(const Vec3<R>& w) {
  return w.z > R(0.0) ? w.z * R(1.0 / kPi) : R(0.0);
}

template <typename R>
Vec3<R> SamplePhongLobe(const Vec3<R>& axis, const R& exponent, const R& u1,
                        const R& u2) {
  using std::pow;
  return AboutAxis(axis, pow(Max(u1, R(1e-30)), R(1.0) / (exponent + R(1.0))),
                   R(2.0 * kPi) * u2);
}

template <typename R>
R PhongLobePdf(const Vec3<R>& axis, const R& exponent, const Vec3<R>& w) {
  using std::pow;
  const R c = glm::dot(axis, w);
  if (!(c > R(0.0))) return R(0.0);
  return (exponent + R(1.0)) * R(0.5 / kPi) * pow(c, exponent);
}

template <typename R>
Vec3<R> MirrorZ(const Vec3<R>& w) {
  return Vec3<R>(w.x, w.y, -w.z);
}

// The sample w moved to the upper hemisphere (see the file comment).
template <typename R>
Vec3<R> MirrorToUpper(const Vec3<R>& w) {
  return w.z < R(0.0) ? MirrorZ(w) : w;
}

// Reflection about a GGX normal visible from wo (Heitz 2018, "Sampling the
// GGX Distribution of Visible Normals", Listing 1; wo.z > 0): h from the
// visible normals' density G1(wo) max(wo.h, 0) D(h) / wo.z, wi the mirror
// of wo about h, so pdf(wi) = G1(wo) D(h) / (4 wo.z) with h = (wi + wo) /
// |wi + wo| (h.z > 0), over the whole sphere (wi may lie below the
// surface). Unlike sampling D(h) cos(theta_h), it never picks an h that
// faces away from wo, and the density has no 1 / |wi + wo| singularity.
template <typename R>
Vec3<R> SampleGgxReflection(const R& alpha, const Vec3<R>& wo, const R& u1,
                            const R& u2) {
  using std::cos;
  using std::sin;
  using std::sqrt;
  const Vec3<R> vh =
      glm::normalize(Vec3<R>(alpha * wo.x, alpha * wo.y, Max(wo.z, R(1e-7))));
  const R lensq = vh.x * vh.x + vh.y * vh.y;
  const Vec3<R> t1 = lensq > R(0.0) ? Vec3<R>(-vh.y, vh.x, R(0.0)) / sqrt(lensq)
                                    : Vec3<R>(R(1.0), R(0.0), R(0.0));
  const Vec3<R> t2 = glm::cross(vh, t1);
  const R r = sqrt(u1), phi = R(2.0 * kPi) * u2;
  const R p1 = r * cos(phi);
  const R s = R(0.5) * (R(1.0) + vh.z);
  const R p2 =
      (R(1.0) - s) * sqrt(Max(R(1.0) - p1 * p1, R(0.0))) + s * r * sin(phi);
  const Vec3<R> nh =
      t1 * p1 + t2 * p2 + vh * sqrt(Max(R(1.0) - p1 * p1 - p2 * p2, R(0.0)));
  const Vec3<R> h =
      glm::normalize(Vec3<R>(alpha * nh.x, alpha * nh.y, Max(nh.z, R(0.0))));
  return h * (R(2.0) * glm::dot(wo, h)) - wo;
}

template <typename R>
R GgxReflectionPdf(const R& alpha, const Vec3<R>& wo, const Vec3<R>& wi) {
  using std::sqrt;
  const Vec3<R> sum = wi + wo;
  const R len = sqrt(glm::dot(sum, sum));
  if (!(len > R(0.0) && wo.z > R(0.0))) return R(0.0);
  const R cos_h = sum.z / len;
  if (!(cos_h > R(0.0))) return R(0.0);
  const R a2 = alpha * alpha;
  const R d = a2 / (R(kPi) * Sqr(cos_h * cos_h * (a2 - R(1.0)) + R(1.0)));
  const R g1 =
      R(2.0) * wo.z / (wo.z + sqrt(a2 * (R(1.0) - wo.z * wo.z) + wo.z * wo.z));
  return g1 * d / (R(4.0) * wo.z);
}

// The longitudinal cone of a thread's specular lobe for the view wo: the
// surface lobe g(gamma_s, theta_h) (Sadeghi et al. 2013, eq. 3) peaks at
// theta_i = -theta_o (theta = asin(w.t)) and, as theta_h = (theta_i +
// theta_o) / 2, has width 2 gamma_s in theta_i. So
//   theta ~ logistic(mu = -theta_o, s = 2 gamma_s sqrt(3) / pi),
//           truncated to [-pi/2, pi/2] (the Gaussian's standard deviation,
//           heavier tails and a closed-form inverse CDF),
//   phi   ~ uniform about t,
// and, with d omega = cos(theta) d theta d phi,
//   pdf(w) = L(theta) / (2 pi cos theta),
//   L(x) = e^-|z| / (s (1 + e^-|z|)^2) / (F(pi/2) - F(-pi/2)),
//   z = (x - mu) / s, F(x) = 1 / (1 + e^-z).
template <typename R>
struct ThreadCone {
  Vec3<R> t, e1, e2;  // axis and a frame of its normal plane
  R mu = R(0.0), s = R(1.0), f_lo = R(0.0), f_hi = R(1.0);
};

template <typename R>
R LogisticCdf(const R& x, const R& mu, const R& s) {
  using std::exp;
  return R(1.0) / (R(1.0) + exp(-(x - mu) / s));
}

// The cone about the tangent t (unit) with local normal n (unit, t.n = 0).
template <typename R>
ThreadCone<R> MakeThreadCone(const Vec3<R>& t, const Vec3<R>& n,
                             const R& gamma_s_deg, const Vec3<R>& wo) {
  using std::asin;
  ThreadCone<R> c;
  c.t = t;
  c.e1 = n;
  c.e2 = glm::cross(t, n);
  c.mu = -asin(Clamp(glm::dot(wo, t), R(-1.0), R(1.0)));
  c.s = R(2.0 * std::sqrt(3.0) / kPi) * Radians(gamma_s_deg);
  c.f_lo = LogisticCdf(R(-0.5 * kPi), c.mu, c.s);
  c.f_hi = LogisticCdf(R(0.5 * kPi), c.mu, c.s);
  return c;
}

template <typename R>
R ThreadConePdf(const ThreadCone<R>& c, const Vec3<R>& w) {
  using std::abs;
  using std::asin;
  using std::exp;
  using std::sqrt;
  const R sin_theta = Clamp(glm::dot(w, c.t), R(-1.0), R(1.0));
  const R cos_theta = sqrt(Max(R(1.0) - sin_theta * sin_theta, R(0.0)));
  if (!(cos_theta > R(0.0))) return R(0.0);  // the axis itself: a null set
  const R e = exp(-abs(asin(sin_theta) - c.mu) / c.s);
  const R logistic = e / (c.s * (R(1.0) + e) * (R(1.0) + e));
  return logistic / (c.f_hi - c.f_lo) / (R(2.0 * kPi) * cos_theta);
}

template <typename R>
Vec3<R> SampleThreadCone(const ThreadCone<R>& c, const R& u1, const R& u2) {
  using std::cos;
  using std::log;
  using std::sin;
  const R f = Clamp(c.f_lo + u1 * (c.f_hi - c.f_lo), R(1e-30), kOneBelow<R>);
  const R theta =
      Clamp(c.mu + c.s * log(f / (R(1.0) - f)), R(-0.5 * kPi), R(0.5 * kPi));
  const R phi = R(2.0 * kPi) * u2;
  return c.t * sin(theta) + (c.e1 * cos(phi) + c.e2 * sin(phi)) * cos(theta);
}

}  // namespace clothfit
