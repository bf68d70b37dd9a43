#include "api/material.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "io/input_error.h"
#include "io/lafortune_mipmap.h"
#include "io/param_mipmap.h"
#include "io/params_json.h"
#include "io/text_util.h"
#include "models/model_sampling.h"

namespace clothfit {

namespace {

// Nearest texel index along an axis of n texels for a coordinate in [0, 1].
template <typename Real>
int TexelIndex(Real u, int n) noexcept {
  if (!(u > 0.0)) return 0;  // also NaN
  const int i = static_cast<int>(u * n);
  return i >= n ? n - 1 : i;
}

// The two texels around coordinate u (texel centres at (i + 0.5) / n,
// clamped at the edges) and the weight of the second.
template <typename Real>
void TexelPair(Real u, int n, int* i0, int* i1, Real* w1) noexcept {
  const Real x = (u > Real(0) ? (u < Real(1) ? u : Real(1)) : Real(0)) * n -
                 Real(0.5);  // NaN: 0
  const Real x0 = std::floor(x);
  *w1 = x - x0;
  const int i = static_cast<int>(x0);
  *i0 = std::clamp(i, 0, n - 1);
  *i1 = std::clamp(i + 1, 0, n - 1);
}

// x with NaN as 0 and infinities saturated at Real's largest value.
template <typename Real>
Real Finite(Real x) noexcept {
  constexpr Real kMax = std::numeric_limits<Real>::max();
  if (!(x == x)) return Real(0);
  return x > kMax ? kMax : (x < -kMax ? -kMax : x);
}

}  // namespace

template <typename Real>
typename MaterialT<Real>::Level MaterialT<Real>::OneTexel(
    const ModelParams& params, const std::string& name) {
  const std::string error = ValidateModel(params);
  if (!error.empty()) throw InputError(name + ": " + error);
  Level level;
  level.texels.push_back(PrepareModel<Real>(params));
  return level;
}

template <typename Real>
MaterialT<Real> MaterialT<Real>::FromParams(const ModelParams& params) {
  MaterialT m;
  m.kind_ = ModelName(params);
  m.levels_.push_back(OneTexel(params, "<parameters>"));
  return m;
}

template <typename Real>
MaterialT<Real> MaterialT<Real>::Load(const std::string& path,
                                      TexelFilter filter) {
  if (!text_util::HasExtension(path, ".exr")) {
    const ParamFile file = ReadParamFile(path);
    const auto* holes = std::get_if<HolesModel>(&file.params);
    if (holes != nullptr && !holes->tile) {
      throw InputError(
          path + ": a holes model needs its mask's tile (key 'tile')" +
          (file.holes.path.empty()
               ? std::string()
               : "; the file names its mask '" + file.holes.path +
                     "', an image, which the renderer API does not read") +
          ": add the tile with 'clothfit holes tile --params " + path +
          " --out FILE'");
    }
    MaterialT m;
    m.kind_ = ModelName(file.params);
    m.levels_.push_back(OneTexel(file.params, path));
    return m;
  }
  const ParamMipmap mipmap = ReadParamMipmap(path);
  MaterialT m;
  m.kind_ = "lafortune_mipmap";
  m.filter_ = filter;
  for (size_t l = 0; l < mipmap.levels.size(); ++l) {
    Level level;
    level.width = mipmap.levels[l].width;
    level.height = mipmap.levels[l].height;
    for (LafortuneModel& texel :
         LevelFromParamMipmap(mipmap, static_cast<int>(l))) {
      level.texels.push_back(PrepareModel<Real>(ModelParams(std::move(texel))));
    }
    m.levels_.push_back(std::move(level));
  }
  if (m.levels_.empty()) throw InputError(path + ": no mip levels");
  return m;
}

template <typename Real>
void MaterialT<Real>::AddLevel(int level, Real s, Real t, Real weight,
                               Taps* taps) const noexcept {
  const Level& l = levels_[ClampLevel(level)];
  auto add = [&](int x, int y, Real w) {
    if (!(w > Real(0))) return;
    taps->texel[taps->count] = &l.texels[static_cast<size_t>(y) * l.width + x];
    taps->weight[taps->count] = w;
    ++taps->count;
  };
  if (filter_ == TexelFilter::kNearest) {
    add(TexelIndex(s, l.width), TexelIndex(t, l.height), weight);
    return;
  }
  int x0, x1, y0, y1;
  Real wx, wy;
  TexelPair(s, l.width, &x0, &x1, &wx);
  TexelPair(t, l.height, &y0, &y1, &wy);
  add(x0, y0, weight * (Real(1) - wx) * (Real(1) - wy));
  add(x1, y0, weight * wx * (Real(1) - wy));
  add(x0, y1, weight * (Real(1) - wx) * wy);
  add(x1, y1, weight * wx * wy);
}

template <typename Real>
typename MaterialT<Real>::Taps MaterialT<Real>::Lookup(
    Real s, Real t, Real lod) const noexcept {
  Taps taps;
  const Real last = static_cast<Real>(levels_.size() - 1);
  lod = lod > Real(0) ? (lod < last ? lod : last) : Real(0);  // NaN: 0
  if (filter_ != TexelFilter::kTrilinear) {
    AddLevel(static_cast<int>(std::lround(lod)), s, t, Real(1), &taps);
  } else {
    const Real l0 = std::floor(lod), w1 = lod - l0;
    AddLevel(static_cast<int>(l0), s, t, Real(1) - w1, &taps);
    AddLevel(static_cast<int>(l0) + 1, s, t, w1, &taps);
  }
  if (taps.count == 0) AddLevel(0, s, t, Real(1), &taps);  // not reached
  return taps;
}

template <typename Real>
typename MaterialT<Real>::Vec MaterialT<Real>::Value(
    const Vec& wi, const Vec& wo, Real s, Real t, Real lod,
    Quantity q) const noexcept {
  // One texel (a parameter file): no lookup.
  if (levels_.size() == 1 && levels_[0].texels.size() == 1) {
    return EvaluatePrepared(levels_[0].texels[0], wi, wo, q);
  }
  const Taps taps = Lookup(s, t, lod);
  if (taps.count == 1) return EvaluatePrepared(*taps.texel[0], wi, wo, q);
  Vec sum(Real(0));
  for (int k = 0; k < taps.count; ++k) {
    sum += taps.weight[k] * EvaluatePrepared(*taps.texel[k], wi, wo, q);
  }
  return Saturate<Real>(sum);
}

template <typename Real>
Real MaterialT<Real>::Pdf(const Vec& wo, const Vec& wi, Real s, Real t,
                          Real lod) const noexcept {
  const Taps taps = Lookup(s, t, lod);
  Real pdf = Real(0);
  for (int k = 0; k < taps.count; ++k) {
    pdf += taps.weight[k] * PreparedWiPdf(*taps.texel[k], wo, wi);
  }
  return Finite(pdf);
}

template <typename Real>
BsdfSampleT<Real> MaterialT<Real>::Sample(const Vec& wo, Real u1, Real u2,
                                          Real s, Real t,
                                          Real lod) const noexcept {
  const Taps taps = Lookup(s, t, lod);
  u1 = u1 > Real(0) ? (u1 < kOneBelow<Real> ? u1 : kOneBelow<Real>) : Real(0);
  u2 = u2 > Real(0) ? (u2 < kOneBelow<Real> ? u2 : kOneBelow<Real>) : Real(0);
  // One texel with the probability of its weight (u1 rescaled), then its
  // sampler; the density is the taps' mixture, as F blends their values.
  const int k =
      taps.count == 1 ? 0 : PickComponent(taps.weight, taps.count, &u1);
  const DirectionSample<Real> d =
      SamplePreparedWi(*taps.texel[k < 0 ? 0 : k], wo, u1, u2);
  BsdfSampleT<Real> out;
  out.wi = d.wi;
  out.delta = d.delta;
  Vec value(Real(0));
  if (d.delta) {
    for (int j = 0; j < taps.count; ++j) {
      out.pdf += taps.weight[j] * PreparedDeltaShare(*taps.texel[j], wo);
      value += taps.weight[j] * PreparedDeltaTransmittance(*taps.texel[j], wo);
    }
  } else {
    out.pdf = taps.count == 1 ? d.pdf : Pdf(wo, d.wi, s, t, lod);
    value = Value(d.wi, wo, s, t, lod, Quantity::kCosineWeighted);
  }
  out.pdf = Finite(out.pdf);
  if (out.pdf > Real(0)) {
    for (int c = 0; c < 3; ++c) out.weight[c] = Finite(value[c] / out.pdf);
  }
  return out;
}

template class MaterialT<double>;
template class MaterialT<float>;

}  // namespace clothfit
