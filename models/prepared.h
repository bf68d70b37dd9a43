// A parameter set made ready for a renderer's inner loop (api/material.h):
// what depends on the parameters alone is computed once per material, and
// the values are evaluated in the renderer's scalar type R (float or
// double) through the same model code as every other caller.
//
// - cloth: the tangent t and local normal n of every sample
//   (MakeTangentFrame: two sine/cosine pairs per sample and evaluation);
// - Lafortune: the texel's frame (MakeTexelFrame of its normal);
// - thread and sheen (glTF): their parameters in R;
// - slab and holes: evaluated in double and rounded to R (their
//   series and limits are written for double).
// A float material whose values can leave float's range (a Lafortune file's
// lobe may peak at 1e100) is evaluated in double too; every float result
// is rounded with saturation at the largest float, so it stays finite.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>
#include <variant>
#include <vector>

#include "models/evaluate.h"

namespace clothfit {

namespace prepared_internal {

// The flat entries (models/params.h ToArray) of `from` into `to`, of
// another scalar type.
template <typename R, typename From, typename To>
void CastFlat(const From& from, To* to) {
  std::vector<double> x(FlatSize(from));
  ToArray(from, x.data());
  std::vector<R> y(x.begin(), x.end());
  FromArray(y.data(), to);
}

template <typename R>
ThreadParamsT<R> CastThread(const ThreadParams& p) {
  ThreadParamsT<R> out;
  CastFlat<R>(p, &out);
  out.scale = R(p.scale);
  out.energy_bound = p.energy_bound;
  return out;
}

}  // namespace prepared_internal

// A cloth with its sample frames (the Frames of ClothRhoWithFrames): a
// thread's samples at the same offset are one frame with its repeats (the
// same terms, added once and multiplied).
template <typename R>
struct PreparedCloth {
  ClothParamsT<R> cloth;
  std::vector<std::vector<TangentFrame<R>>> frames;  // [thread][distinct]

  int Count(size_t j) const { return static_cast<int>(frames[j].size()); }
  // The thread's samples, repeats included.
  int Total(size_t j) const {
    return static_cast<int>(cloth.threads[j].offsets_deg.size());
  }
  const TangentFrame<R>& Get(size_t j, int k) const { return frames[j][k]; }
};

template <typename R>
PreparedCloth<R> PrepareCloth(const ClothParams& c) {
  PreparedCloth<R> out;
  out.cloth.rotation_deg = R(c.rotation_deg);
  out.cloth.diffuse = Cast<R>(c.diffuse);
  out.cloth.scale = R(c.scale);
  out.cloth.energy_bound = c.energy_bound;
  for (const ClothThread& th : c.threads) {
    ClothThreadT<R> t;
    t.direction = th.direction;
    t.coverage = R(th.coverage);
    t.offsets_deg.assign(th.offsets_deg.begin(), th.offsets_deg.end());
    t.curve = th.curve;
    t.params = prepared_internal::CastThread<R>(th.params);
    out.cloth.threads.push_back(t);
    // The frames from the double parameters, then rounded: the same frames
    // as a double evaluation, to R's precision.
    std::vector<TangentFrame<R>> frames;
    std::vector<double> offsets;  // of `frames`
    for (double offset : th.offsets_deg) {
      const auto same = std::find(offsets.begin(), offsets.end(), offset);
      if (same != offsets.end()) {
        ++frames[same - offsets.begin()].repeats;
        continue;
      }
      const TangentFrame<double> f =
          MakeTangentFrame(th.direction, c.rotation_deg, offset);
      frames.push_back({Cast<R>(f.t), Cast<R>(f.n), 1});
      offsets.push_back(offset);
    }
    out.frames.push_back(std::move(frames));
  }
  return out;
}

// A Lafortune texel with its frame, its grey lobes and whether its frame is
// the surface's (LafortuneShape).
template <typename R>
struct PreparedLafortune {
  LafortuneParamsT<R> params;
  TexelFrameT<R> frame;
  ViewTable lut;
  LafortuneShape shape;
};

template <typename R>
PreparedLafortune<R> PrepareLafortune(const LafortuneModel& m) {
  PreparedLafortune<R> out;
  out.params.diffuse = Cast<R>(m.params.diffuse);
  for (const LafortuneLobe& lobe : m.params.lobes) {
    LafortuneLobeT<R> l;
    prepared_internal::CastFlat<R>(lobe, &l);
    out.params.lobes.push_back(l);
  }
  const TexelFrame f = MakeTexelFrame(m.normal);
  out.frame.t = Cast<R>(f.t);
  out.frame.b = Cast<R>(f.b);
  out.frame.n = Cast<R>(f.n);
  out.lut = m.lut;
  out.shape = MakeLafortuneShape(out.params, out.frame);
  return out;
}

// Whether a Lafortune texel's values stay well inside float's range: every
// |C| and rho_d below 1e30 and every lobe's peak max|C|^N below 1e30.
inline bool LafortuneFitsFloat(const LafortuneModel& m) {
  constexpr double kLimit = 1e30;
  for (int c = 0; c < 3; ++c) {
    if (!(m.params.diffuse[c] < kLimit)) return false;
    for (const LafortuneLobe& lobe : m.params.lobes) {
      const double reach = std::max(
          {std::abs(lobe.cx[c]), std::abs(lobe.cy[c]), std::abs(lobe.cz[c])});
      if (!(reach < kLimit)) return false;
      if (reach > 1.0 && !(lobe.n[c] * std::log10(reach) < 30.0)) return false;
    }
  }
  return true;
}

// A parameter set prepared for scalar type R: one of the prepared forms
// above, or the double parameters themselves (slab, holes, and float
// materials beyond float's range).
template <typename R>
using PreparedModel =
    std::variant<ThreadParamsT<R>, PreparedCloth<R>, PreparedLafortune<R>,
                 SheenParamsT<R>, ModelParams>;

template <typename R>
PreparedModel<R> PrepareModel(const ModelParams& params) {
  if (const auto* t = std::get_if<ThreadParams>(&params)) {
    return prepared_internal::CastThread<R>(*t);
  }
  if (const auto* c = std::get_if<ClothParams>(&params)) {
    return PrepareCloth<R>(*c);
  }
  if (const auto* g = std::get_if<SheenParams>(&params)) {
    SheenParamsT<R> out;
    prepared_internal::CastFlat<R>(*g, &out);
    return out;
  }
  if (const auto* m = std::get_if<LafortuneModel>(&params)) {
    if (std::is_same_v<R, double> || LafortuneFitsFloat(*m)) {
      return PrepareLafortune<R>(*m);
    }
  }
  return params;
}

template <typename R>
inline constexpr ModelInfo kModelInfo<PreparedCloth<R>> =
    kModelInfo<ClothParams>;
template <typename R>
inline constexpr ModelInfo kModelInfo<PreparedLafortune<R>> =
    kModelInfo<LafortuneModel>;

// Inlined whole (CLOTHFIT_INLINE_ALL): GCC otherwise calls the projection
// and the lobes of each tangent sample out of line (the satin 1.2x
// slower).
template <typename R>
CLOTHFIT_INLINE_ALL Vec3<R> NativeValue(const PreparedCloth<R>& p,
                                        const Vec3<R>& wi, const Vec3<R>& wo) {
  return ClothRhoWithFrames(p.cloth, p, wi, wo) *
         (p.cloth.scale *
          EnergyBoundFactor(p.cloth.energy_bound.get(), wi.z, wo.z));
}

template <typename R>
CLOTHFIT_INLINE_ALL Vec3<R> NativeValue(const PreparedLafortune<R>& p,
                                        const Vec3<R>& wi, const Vec3<R>& wo) {
  return LafortuneRhoInFrame(p.params, p.frame, p.lut, wi, wo, &p.shape);
}

// A value as R, saturated at R's largest finite value (a float
// evaluation of extreme parameters may overflow where double does not).
template <typename R, typename V>
Vec3<R> Saturate(const glm::vec<3, V>& v) {
  constexpr V kMax = static_cast<V>(std::numeric_limits<R>::max());
  Vec3<R> out;
  for (int c = 0; c < 3; ++c) out[c] = R(Clamp(v[c], -kMax, kMax));
  return out;
}

// The value of a prepared model as quantity q (models/evaluate.h Value).
template <typename R>
Vec3<R> EvaluatePrepared(const PreparedModel<R>& model, const Vec3<R>& wi,
                         const Vec3<R>& wo, Quantity q) {
  return std::visit(
      [&](const auto& p) -> Vec3<R> {
        using P = std::decay_t<decltype(p)>;
        if constexpr (std::is_same_v<P, ModelParams>) {
          const glm::dvec3 v = Evaluate(p, glm::dvec3(wi), glm::dvec3(wo), q);
          if constexpr (std::is_same_v<R, double>) {
            return v;
          } else {
            return Saturate<R>(v);
          }
        } else if constexpr (std::is_same_v<R, double>) {
          return Value(p, wi, wo, q);
        } else {
          return Saturate<R>(Value(p, wi, wo, q));
        }
      },
      model);
}

}  // namespace clothfit
