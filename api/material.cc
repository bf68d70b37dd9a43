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
int TexelIndex(double u, int n) noexcept {
  if (!(u > 0.0)) return 0;  // also NaN
  const int i = static_cast<int>(u * n);
  return i >= n ? n - 1 : i;
}

}  // namespace

Material::Level Material::OneTexel(const ModelParams& params,
                                   const std::string& name) {
  const std::string error = ValidateModel(params);
  if (!error.empty()) throw InputError(name + ": " + error);
  Level level;
  level.texels.push_back(params);
  return level;
}

Material Material::FromParams(const ModelParams& params) {
  Material m;
  m.kind_ = ModelName(params);
  m.levels_.push_back(OneTexel(params, "<parameters>"));
  return m;
}

Material Material::Load(const std::string& path) {
  if (!text_util::HasExtension(path, ".exr")) {
    const ParamFile file = ReadParamFile(path);
    Material m;
    m.kind_ = ModelName(file.params);
    m.levels_.push_back(OneTexel(file.params, path));
    return m;
  }
  const ParamMipmap mipmap = ReadParamMipmap(path);
  Material m;
  m.kind_ = "lafortune_mipmap";
  for (size_t l = 0; l < mipmap.levels.size(); ++l) {
    Level level;
    level.width = mipmap.levels[l].width;
    level.height = mipmap.levels[l].height;
    for (LafortuneModel& texel :
         LevelFromParamMipmap(mipmap, static_cast<int>(l))) {
      level.texels.push_back(std::move(texel));
    }
    m.levels_.push_back(std::move(level));
  }
  if (m.levels_.empty()) throw InputError(path + ": no mip levels");
  return m;
}

glm::dvec3 Material::Value(const glm::dvec3& wi, const glm::dvec3& wo, double s,
                           double t, int level, Quantity q) const noexcept {
  const Level& l = levels_[ClampLevel(level)];
  const size_t i = static_cast<size_t>(TexelIndex(t, l.height)) * l.width +
                   TexelIndex(s, l.width);
  return Evaluate(l.texels[i], wi, wo, q);
}

}  // namespace clothfit
