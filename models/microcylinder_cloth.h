// Cloth patch of the microcylinder model (Sadeghi et al. 2013, eq. 5-13;
// docs/models.md): threads of a weave with coverages and tangent samples,
// shadowing/masking M and reweighting P. Templated on the scalar type.
//
// For thread j (direction d = +x for "u", +y for "v") with tangent samples at
// offsets psi (rotations of the tangent towards +z):
//   t   = cos(psi) d + sin(psi) z,   n_t = -sin(psi) d + cos(psi) z
//   u(x) = exp(-x^2 / (2 (20 deg)^2))                           (eq. 9)
//   M = (1 - u(phi_d)) max(cos phi_i, 0) max(cos phi_o, 0)
//       + u(phi_d) min(max(cos phi_i, 0), max(cos phi_o, 0))     (eq. 8)
//   P = the same with psi in place of phi                        (eq. 10)
//   S_j = 1/T_j sum_t f_s(t) M(t) P(t) cos(theta_i(t))           (eq. 11)
//   W_j = 1/T_j sum_t P(t)
//   Q   = sum_j a_j W_j + (1 - sum_j a_j) wi.z                   (eq. 12-13)
//   rho = sum_j a_j S_j / Q   (0 where Q <= 0),  f = rho / wi.z.
// Reflection only: rho = 0 unless wi.z > 0 and wo.z > 0.
//
// Two optional freedoms that are not in the paper (both 0 by default, which
// is the paper's model):
// - rotation_deg: the weave turned about the normal, so that the warp runs
//   along (cos r, sin r, 0) and the weft along (-sin r, cos r, 0). A
//   measured sample's orientation on the gonioreflectometer is often
//   unknown (CUReT's is).
// - diffuse: a Lambertian term f_d = diffuse / pi added outside the
//   normalisation Q (rho += diffuse wi.z / pi): light that the threads'
//   lobes do not describe (multiple scattering between fibres, loose
//   fibres, the backing). It is energy conserving when diffuse plus the
//   threads' own directional albedo stays <= 1.
#pragma once

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "models/math.h"
#include "models/microcylinder_thread.h"
#include "models/params.h"
#include "models/tangent_curve.h"

namespace clothfit {

enum class ThreadDirection { kU, kV };  // warp along +x, weft along +y

// The weave's own entries (models/params.h).
inline constexpr ParamInfo kClothRotation = {
    "rotation_deg",
    "degrees",
    "rotation of the weave about the normal (warp along (cos r, sin r, 0))",
    {-360.0, 360.0},
    -360.0,
    360.0,
    false,
    {0.0},
    "clothfit: a measured sample's unknown orientation",
    1};
inline constexpr ParamInfo kClothDiffuse = {
    "diffuse",
    "unitless",
    "albedo of a Lambertian term outside the normalisation (f += diffuse/pi)",
    {0.0, 1.0},
    0.0,
    1.0,
    true,
    {0.0, 0.0, 0.0},
    "clothfit: what the threads' lobes leave (fibre interreflection)",
    3};

// The parameter table of a weave's threads (models/params.h); each thread
// also has the thread entries of models/microcylinder_thread.h.
inline constexpr ParamInfo kClothCoverage = {
    "coverage",
    "unitless",
    "fraction of the patch a thread covers (the threads' sum <= 1)",
    {0.0, 1.0},
    0.0,
    1.0,
    true,
    {0.33},
    "Sadeghi et al. 2013, eq. 12 (a_j), Table 3",
    1};
inline constexpr ParamInfo kClothOffsets = {
    "offsets_deg",
    "degrees",
    "tangent offsets psi of a thread's samples (rotation towards +z)",
    {-90.0, 90.0},
    -90.0,
    90.0,
    true,
    {0.0},
    "Sadeghi et al. 2013, eq. 11 (C_j), Table 3",
    1};

// One thread type of a weave.
template <typename T>
struct ClothThreadT {
  // Direction of the thread in the surface frame (docs/formats.md).
  ThreadDirection direction = ThreadDirection::kU;
  T coverage = kClothCoverage.Default<T>();  // a_j
  // The tangent offsets of the samples C_j. No default: a weave's samples
  // always come from a file or a preset.
  std::vector<T> offsets_deg;
  // When the file gave a tangent curve, the curve (offsets_deg holds its
  // samples); curve.samples == 0 means the samples were given explicitly.
  TangentCurve curve;
  // Scattering parameters of the thread (eq. 2-4).
  ThreadParamsT<T> params;
};

template <typename T>
struct ClothParamsT {
  std::vector<ClothThreadT<T>> threads;
  T rotation_deg = kClothRotation.Default<T>();     // kClothRotation
  Vec3<T> diffuse = kClothDiffuse.DefaultRgb<T>();  // kClothDiffuse
  T scale = kModelScale.Default<T>();               // kModelScale
  // models/energy_bound.h; null: the paper's model as it is.
  std::shared_ptr<const EnergyBound> energy_bound;
};
using ClothThread = ClothThreadT<double>;
using ClothParams = ClothParamsT<double>;

// "threads[j]." for messages and report names.
inline std::string ClothThreadPrefix(size_t j) {
  return "threads[" + std::to_string(j) + "].";
}

// Checks every thread's entries against the tables and the coverages' sum;
// "" when valid, else a message naming the entry by its path
// ("threads[1].kd: must be in [0, 1], got 2").
inline std::string ValidateClothParams(const ClothParams& c) {
  if (c.threads.empty()) return "threads: at least one thread is required";
  double sum = 0.0;
  for (size_t j = 0; j < c.threads.size(); ++j) {
    const ClothThread& th = c.threads[j];
    const std::string where = ClothThreadPrefix(j);
    std::string e = CheckParam(kClothCoverage, th.coverage);
    if (!e.empty()) return where + e;
    sum += th.coverage;
    if (th.offsets_deg.empty()) {
      return where + "offsets_deg: at least one tangent sample is required";
    }
    for (double o : th.offsets_deg) {
      e = CheckParam(kClothOffsets, o);
      if (!e.empty()) return where + e;
    }
    e = ValidateParams(th.params);
    if (!e.empty()) return where + e;
  }
  if (sum > 1.0 + 1e-9) {
    std::ostringstream msg;
    msg << "threads: coverages sum to " << sum << ", must be <= 1";
    return msg.str();
  }
  std::string e = CheckParam(kClothRotation, c.rotation_deg);
  for (int k = 0; k < 3 && e.empty(); ++k) {
    e = CheckParam(kClothDiffuse, c.diffuse[k]);
  }
  if (!e.empty()) return e;
  return CheckParam(kModelScale, c.scale);
}

// u(angle_d) of eq. 9: the weight of the min term in M and P.
template <typename T>
T MaskingBlend(const T& angle_d) {
  constexpr double kWidth = Radians(20.0);
  return ExpNeg(angle_d * angle_d / T(2.0 * kWidth * kWidth));
}

// Shadowing/masking M (eq. 8) or reweighting P (eq. 10) from the cosines of
// the two projections and u = MaskingBlend(angle between them), which
// `blend()` returns: it is asked for only when both cosines are > 0, as
// both terms vanish otherwise (value and derivative).
template <typename T, typename Blend>
T MaskingTermWith(const T& cos_i, const T& cos_o, const Blend& blend) {
  if (!(cos_i > T(0.0) && cos_o > T(0.0))) return T(0.0);
  const T u = blend();
  return (T(1.0) - u) * cos_i * cos_o + u * Min(cos_i, cos_o);
}

template <typename T>
T MaskingTerm(const T& cos_i, const T& cos_o, const T& angle_d) {
  return MaskingTermWith(cos_i, cos_o, [&] { return MaskingBlend(angle_d); });
}

// One tangent sample of a thread seen from (wi, wo): its geometry and the
// factors that depend on geometry alone.
template <typename G>
struct TangentSample {
  bool valid = false;  // both projections defined (else it contributes 0)
  // Complete only where weight > 0 (ComputeTangentSample); the lobes read
  // it there alone.
  ThreadGeometry<G> geometry;
  G weight = G(0.0);    // M P cos(theta_i): multiplies f_s in S_j (eq. 11)
  G reweight = G(0.0);  // P: the sample's term of W_j (eq. 12)
};

// What the samples of one thread share: the axis b = t x n is d x z for
// every tangent offset, so the projections of wi and wo on the (t, n)
// plane (psi of eq. 10), their lengths, the angle psi_d between them and
// its blend u are the thread's; only cos psi against each sample's n
// differs. `valid` is false where a projection vanishes (no sample of the
// thread contributes).
template <typename G>
struct PsiPlane {
  bool valid = false;
  Vec3<G> qi, qo;
  G qi_len, qo_len;
  G inv_qi_len, inv_qo_len;
  G wi_b, wo_b;  // wi.b and wo.b (ProjectOnThread)
  G u;           // MaskingBlend(psi_d)
};

// The direction of a thread in the surface frame: +x (warp, "u") or +y
// (weft, "v"), turned by the weave's rotation about the normal.
template <typename G>
Vec3<G> ThreadAxis(ThreadDirection direction, const G& rotation_deg) {
  using std::cos;
  using std::sin;
  const G r = Radians(rotation_deg);
  const G c = cos(r), s = sin(r);
  return direction == ThreadDirection::kU ? Vec3<G>(c, s, G(0.0))
                                          : Vec3<G>(-s, c, G(0.0));
}

// The tangent t and local normal n of a sample at tangent offset
// `offset_deg` of a thread along `direction` in a weave turned by
// `rotation_deg`: t = cos(psi) d + sin(psi) z, n = cos(psi) z - sin(psi) d.
// They depend on the parameters alone, so a renderer computes them once
// per material (models/prepared.h).
template <typename G>
struct TangentFrame {
  Vec3<G> t, n;
  // How many of the thread's samples the frame stands for: 1, or more
  // where a prepared material merges samples at the same offset (the
  // satin's Table 3 offsets repeat -32, 0 and 32 degrees).
  int repeats = 1;
};

template <typename G>
TangentFrame<G> MakeTangentFrame(ThreadDirection direction,
                                 const G& rotation_deg, const G& offset_deg) {
  using std::cos;
  using std::sin;
  const Vec3<G> d = ThreadAxis(direction, rotation_deg);
  const Vec3<G> z(G(0.0), G(0.0), G(1.0));
  const G psi = Radians(offset_deg);
  const G c = cos(psi), s = sin(psi);
  return {d * c + z * s, z * c - d * s, 1};
}

// The psi plane of the thread of frame f (any of its samples).
template <typename G>
PsiPlane<G> MakePsiPlane(const TangentFrame<G>& f, const Vec3<G>& wi,
                         const Vec3<G>& wo) {
  using std::sqrt;
  PsiPlane<G> plane;
  const Vec3<G> b = glm::cross(f.t, f.n);
  plane.qi = wi - b * glm::dot(wi, b);
  plane.qo = wo - b * glm::dot(wo, b);
  const G qi2 = glm::dot(plane.qi, plane.qi);
  const G qo2 = glm::dot(plane.qo, plane.qo);
  const G kMin(kMinProjectionLength2);
  if (!(qi2 > kMin && qo2 > kMin)) return plane;
  plane.valid = true;
  plane.qi_len = sqrt(qi2);
  plane.qo_len = sqrt(qo2);
  plane.inv_qi_len = G(1.0) / plane.qi_len;
  plane.inv_qo_len = G(1.0) / plane.qo_len;
  plane.wi_b = glm::dot(wi, b);
  plane.wo_b = glm::dot(wo, b);
  plane.u = MaskingBlend(
      AngleBetween(plane.qi, plane.qo, plane.qi_len * plane.qo_len));
  return plane;
}

// The sample of frame f seen from (wi, wo), its thread's psi plane given.
// The geometry is completed only as far as the masking terms leave the
// sample a share: without P (eq. 10) it adds nothing to W_j, without M
// (eq. 8) nothing to S_j, and the lobes' angles (theta_h, theta_d,
// phi_d / 2) are computed only for a positive weight, the one case
// ThreadSums reads them.
template <typename G>
TangentSample<G> ComputeTangentSample(const TangentFrame<G>& f,
                                      const PsiPlane<G>& plane,
                                      const Vec3<G>& wi, const Vec3<G>& wo) {
  TangentSample<G> out;
  if (!plane.valid) return out;  // contributes nothing
  ThreadGeometry<G>& g = out.geometry;
  ThreadAzimuths<G> azimuths;
  if (!ProjectOnThread(f.t, f.n, plane.wi_b, plane.wo_b, wi, wo, &g,
                       &azimuths)) {
    return out;
  }
  out.valid = true;
  // cos psi of eq. 10: q.n / |q|, and q.n = w.n (q is w less its part
  // along b, which is normal to n).
  out.reweight = MaskingTermWith(G(glm::dot(wi, f.n) * plane.inv_qi_len),
                                 G(glm::dot(wo, f.n) * plane.inv_qo_len),
                                 [&] { return plane.u; });
  if (!(out.reweight > G(0.0))) return out;
  ThreadAzimuthDifference(azimuths, &g);
  out.weight = MaskingTerm(g.cos_phi_i, g.cos_phi_o, g.phi_d) * out.reweight *
               g.cos_theta_i;
  if (out.weight > G(0.0)) ThreadHalfAngles(azimuths, &g);
  return out;
}

template <typename G>
TangentSample<G> ComputeTangentSample(ThreadDirection direction,
                                      const G& rotation_deg,
                                      const G& offset_deg, const Vec3<G>& wi,
                                      const Vec3<G>& wo) {
  const TangentFrame<G> f =
      MakeTangentFrame(direction, rotation_deg, offset_deg);
  return ComputeTangentSample(f, MakePsiPlane(f, wi, wo), wi, wo);
}

// A cloth's samples seen from (wi, wo), computed as ThreadSums asks for
// them (the Samples of ClothRhoFromSamples): frames.Count(j) and
// frames.Get(j, k) give thread j's distinct sample frames, frames.Total(j)
// the number of samples they stand for (the sum of their repeats); the psi
// plane is computed once per thread, at the first sample asked for. A
// frame's repeats multiply its sample's weights.
template <typename G, typename Frames>
class SamplesFromFrames {
 public:
  SamplesFromFrames(const Frames& frames, const Vec3<G>& wi, const Vec3<G>& wo)
      : frames_(frames), wi_(wi), wo_(wo) {}
  int Count(size_t j) const { return frames_.Count(j); }
  int Total(size_t j) const { return frames_.Total(j); }
  TangentSample<G> Get(size_t j, int k) const {
    const TangentFrame<G> f = frames_.Get(j, k);
    if (j != plane_thread_) {
      plane_ = MakePsiPlane(f, wi_, wo_);
      plane_thread_ = j;
    }
    TangentSample<G> sample = ComputeTangentSample(f, plane_, wi_, wo_);
    if (f.repeats != 1) {
      sample.weight *= G(f.repeats);
      sample.reweight *= G(f.repeats);
    }
    return sample;
  }
  template <typename T>
  ThreadLobes<T> Lobes(size_t, int, const TangentSample<G>& sample,
                       const ThreadLobeParams<T>& params) const {
    return ThreadLobesOf(sample.geometry, params);
  }

 private:
  const Frames& frames_;
  const Vec3<G>& wi_;
  const Vec3<G>& wo_;
  mutable PsiPlane<G> plane_;
  mutable size_t plane_thread_ = static_cast<size_t>(-1);
};

// Thread j's sums of eq. 11-12 over its samples: S_j = (1/T_j) sum_t f_s M
// P cos(theta_i) and W_j = (1/T_j) sum_t P (both 0 without samples).
// `samples.Count(j)` and `samples.Get(j, k)` give thread j's samples (a
// TangentSample<G>, its weights multiplied by the number of samples it
// stands for), `samples.Total(j)` that number T_j summed, and
// `samples.Lobes(j, k, sample, lobe_params)` their ThreadLobes
// (ThreadLobesOf, or the same with a Fresnel term computed once). The
// lobes are summed as scalars and the albedo applied once.
template <typename T, typename G, typename Samples>
void ThreadSums(const ThreadParamsT<T>& params, const Samples& samples,
                size_t j, Vec3<T>* s_j, G* w_j) {
  T surface(0.0), volume(0.0);
  G w(0.0);
  const ThreadLobeParams<T> lobe_params(params);
  const int count = samples.Count(j);
  for (int k = 0; k < count; ++k) {
    const TangentSample<G>& sample = samples.Get(j, k);
    if (!sample.valid) continue;
    w += sample.reweight;
    if (sample.weight > G(0.0)) {
      const ThreadLobes<T> lobes = samples.Lobes(j, k, sample, lobe_params);
      surface += lobes.surface * T(sample.weight);
      volume += lobes.volume * T(sample.weight);
    }
  }
  const int total = samples.Total(j);
  const double inv_count = total > 0 ? 1.0 / total : 0.0;
  *s_j = (Vec3<T>(surface) + params.albedo * volume) * T(inv_count);
  *w_j = w * G(inv_count);
}

// The normalisation of eq. 12-13, Q = sum_j a_j W_j + (1 - sum_j a_j) wi.z
// (the threads' reweighted coverage and the gaps' foreshortened one),
// summed thread by thread.
template <typename T>
struct ClothNormalisation {
  T weighted = T(0.0), coverage = T(0.0);

  void Add(const T& a_j, const T& w_j) {
    coverage += a_j;
    weighted += a_j * w_j;
  }
  template <typename G>
  T Q(const G& wi_z) const {
    return weighted + (T(1.0) - coverage) * T(wi_z);
  }
};

// rho from the samples of every thread (eq. 11-13): sum_j a_j S_j / Q
// (ClothNormalisation), plus the Lambertian term diffuse wi.z / pi; cloth
// gives the coverages, scattering parameters and diffuse (its offsets and
// rotation are not read: they made the samples). ClothRho computes the
// samples on the fly; a fit with fixed directions and offsets passes samples
// it computed once.
template <typename T, typename G, typename Samples>
Vec3<T> ClothRhoFromSamples(const ClothParamsT<T>& cloth,
                            const Samples& samples, const G& wi_z) {
  const Vec3<T> zero(T(0.0));
  Vec3<T> sum = zero;
  ClothNormalisation<T> normalisation;
  for (size_t j = 0; j < cloth.threads.size(); ++j) {
    const ClothThreadT<T>& th = cloth.threads[j];
    Vec3<T> s_j;
    G w_j;
    ThreadSums(th.params, samples, j, &s_j, &w_j);
    sum += s_j * th.coverage;
    normalisation.Add(th.coverage, T(w_j));
  }
  const Vec3<T> diffuse = cloth.diffuse * T(wi_z / kPi);
  const T q = normalisation.Q(wi_z);
  if (!(q > T(0.0))) return diffuse;
  return sum / q + diffuse;
}

// Cosine-weighted BRDF rho(wi, wo) = f |wi.z| of a cloth patch, per
// channel, with the sample frames from `frames` (SamplesFromFrames): made
// from the offsets on the fly (ClothRho), or once per material
// (models/prepared.h).
template <typename T, typename Frames>
Vec3<T> ClothRhoWithFrames(const ClothParamsT<T>& cloth, const Frames& frames,
                           const Vec3<T>& wi, const Vec3<T>& wo) {
  if (!(wi.z > T(0.0) && wo.z > T(0.0))) return Vec3<T>(T(0.0));
  return ClothRhoFromSamples(
      cloth, SamplesFromFrames<T, Frames>(frames, wi, wo), wi.z);
}

// The frames of a cloth's samples from its offsets and rotation.
template <typename T>
struct ClothFramesOnTheFly {
  const ClothParamsT<T>& cloth;
  int Count(size_t j) const {
    return static_cast<int>(cloth.threads[j].offsets_deg.size());
  }
  int Total(size_t j) const { return Count(j); }
  TangentFrame<T> Get(size_t j, int k) const {
    const ClothThreadT<T>& th = cloth.threads[j];
    return MakeTangentFrame(th.direction, cloth.rotation_deg,
                            th.offsets_deg[k]);
  }
};

template <typename T>
Vec3<T> ClothRho(const ClothParamsT<T>& cloth, const Vec3<T>& wi,
                 const Vec3<T>& wo) {
  return ClothRhoWithFrames(cloth, ClothFramesOnTheFly<T>{cloth}, wi, wo);
}

template <typename T>
inline constexpr ModelInfo kModelInfo<ClothParamsT<T>> = {
    "cloth", Quantity::kCosineWeighted, false};

// A cloth patch in the surface frame: rho (eq. 13) times the model's
// scale, bounded by its energy bound.
template <typename T, typename G>
Vec3<T> NativeValue(const ClothParamsT<T>& c, const Vec3<G>& wi,
                    const Vec3<G>& wo) {
  return ClothRho(c, Cast<T>(wi), Cast<T>(wo)) *
         (c.scale * T(EnergyBoundFactor(c.energy_bound.get(), wi.z, wo.z)));
}

}  // namespace clothfit
