#include "api/material.h"

#include <algorithm>
#include <cmath>

#include "io/input_error.h"
#include "io/lafortune_mipmap.h"
#include "io/param_mipmap.h"
#include "io/params_json.h"
#include "io/text_util.h"

namespace clothfit {

namespace {

// Nearest texel index along an axis of n texels for a coordinate in [0, 1].
template <typename Real>
int TexelIndex(Real u, int n) noexcept {
  if (!(u > 0.0)) return 0;  // also NaN
  const int i = static_cast<int>(u * n);
  return i >= n ? n - 1 : i;
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
MaterialT<Real> MaterialT<Real>::Load(const std::string& path) {
  if (!text_util::HasExtension(path, ".exr")) {
    const ParamFile file = ReadParamFile(path);
    MaterialT m;
    m.kind_ = ModelName(file.params);
    m.levels_.push_back(OneTexel(file.params, path));
    return m;
  }
  const ParamMipmap mipmap = ReadParamMipmap(path);
  MaterialT m;
  m.kind_ = "lafortune_mipmap";
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
typename MaterialT<Real>::Vec MaterialT<Real>::Value(
    const Vec& wi, const Vec& wo, Real s, Real t, int level,
    Quantity q) const noexcept {
  const Level& l = levels_[ClampLevel(level)];
  const size_t i = static_cast<size_t>(TexelIndex(t, l.height)) * l.width +
                   TexelIndex(s, l.width);
  return EvaluatePrepared(l.texels[i], wi, wo, q);
}

template class MaterialT<double>;
template class MaterialT<float>;

}  // namespace clothfit
