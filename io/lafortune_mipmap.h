// The layout of a Lafortune parameter mip map (io/param_mipmap.h): one
// level per mip level of a spatially varying fit (Daubert et al. 2001,
// Section 5.1), each texel's model (models/lafortune.h) as named channels:
//   "lobes", "relative_rms", "normal.{X,Y,Z}", "diffuse.{R,G,B}",
//   "lobe{k}.{Cx,Cy,Cz,N}.{R,G,B}" for k below the largest lobe count,
//   "lut.{v}.{R,G,B,A}" per view v,
// with the entries' names from the parameter table (kLafortuneDiffuse,
// kLafortuneCx, ...), and the views and units in the index's metadata.
// Texels with fewer lobes have zeros in the others.
#pragma once

#include <vector>

#include "io/param_mipmap.h"
#include "models/lafortune.h"

namespace clothfit {

// One level: its texels' models and their fits' relative RMS errors.
struct LafortuneTexelMap {
  int width = 0, height = 0;
  std::vector<LafortuneModel> texels;  // y * width + x
  std::vector<double> relative_rms;    // per texel (empty: 0)
};

// The mip map of `levels` (level 0 first) whose lookup tables share
// `views` (surface frame).
ParamMipmap ToParamMipmap(const std::vector<LafortuneTexelMap>& levels,
                          const std::vector<glm::dvec3>& views);

// Texel (x, y) of `level` read back from a mip map written by
// ToParamMipmap (its metadata holds the views). Throws InputError for a
// level or texel out of range and a missing channel.
LafortuneModel TexelFromParamMipmap(const ParamMipmap& mipmap, int level, int x,
                                    int y);
// Every texel of `level` (y * width + x), reading the index once: what a
// renderer loads (api/material.h).
std::vector<LafortuneModel> LevelFromParamMipmap(const ParamMipmap& mipmap,
                                                 int level);

}  // namespace clothfit
