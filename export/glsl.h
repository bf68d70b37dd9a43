// GLSL ES 3.00 of a fitted model (`clothfit export --format glsl`): the
// model's functions (export/glsl/*.glsl, the one second copy of the
// formulas of models/, kept equal by tests/glsl_browser_test.cc) with the
// parameters as constants, ready to paste into a renderer's shader:
//
//   vec3 clothfit_f(vec3 wi, vec3 wo);    // the BSDF f, 1/sr, per channel
//   vec3 clothfit_rho(vec3 wi, vec3 wo);  // rho = f |wi.z|
//   vec3 clothfit_direct_transmittance(vec3 w);  // slab only
//   vec3 clothfit_transmittance(vec3 wo);  // holes only (f = rho = 0)
//
// wi, wo unit vectors in the surface frame (normal +z, warp +x; a thread:
// the thread frame, tangent +x), pointing away from the surface.
#pragma once

#include <string>
#include <vector>

#include "api/material.h"
#include "io/lafortune_mipmap.h"
#include "models/evaluate.h"

namespace clothfit {

// Throws InputError for a model without a GLSL form (sheen: the glTF
// export gives the sheen to renderers), a holes model without its tile or
// with more than 16 texels in it.
std::string GlslSource(const ModelParams& model);

// A Lafortune parameter mip map: GLSL whose parameters live in a
// mip-mapped texture array the renderer binds (export/glsl/
// lafortune_map.glsl gives the layout), and that array's texels: level by
// level, layer by layer, row by row (row 0 of the map first), RGBA
// float32. Entry points clothfit_f_map / clothfit_rho_map(vec2 st, float
// lod, vec3 wi, vec3 wo), filtered as `filter` (api/material.h).
struct GlslMap {
  std::string source;
  std::vector<float> texels;
  int layers = 0;
};
GlslMap GlslMapSource(const std::vector<LafortuneTexelMap>& levels,
                      const std::vector<glm::dvec3>& views, TexelFilter filter);

}  // namespace clothfit
