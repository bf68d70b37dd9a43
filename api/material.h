// The stable evaluation API for renderers: load a parameter file
// or a Lafortune parameter mip map once, then evaluate f or rho for
// (wi, wo) in a renderer's inner loop.
//
//   clothfit::Material m = clothfit::Material::Load("satin.json");
//   glm::dvec3 f = m.F(wi, wo);               // BRDF, 1/sr
//   glm::dvec3 rho = m.Rho(wi, wo, s, t, 2);  // mip map: texel (s, t), level 2
//
// Directions are unit vectors in the surface frame (SPEC §1: normal +z,
// warp/u along +x, weft/v along +y), both pointing away from the surface;
// for a thread file, in the thread frame (tangent +x, SPEC §3.1).
// Loading throws InputError (io/input_error.h) naming the file and the
// problem. Evaluation never throws, never allocates, and only reads the
// loaded data, so any number of threads may evaluate one Material at once.
// For a slab, f is the reflection or transmission BSDF (wi and wo on
// opposite sides: transmission).
#pragma once

#include <string>
#include <vector>

#include "models/evaluate.h"

namespace clothfit {

class Material {
 public:
  // A parameter file of any model (SPEC §4: thread, cloth, lafortune, slab)
  // or, for a path ending in ".exr", a parameter mip map written by
  // `clothfit fit --model lafortune` on a table with s,t columns.
  static Material Load(const std::string& path);
  // A parameter set already in memory (e.g. a preset, models/presets.h).
  // Throws InputError when a field is out of range.
  static Material FromParams(const ModelParams& params);

  // "thread" | "cloth" | "lafortune" | "slab" | "lafortune_mipmap".
  const std::string& Kind() const { return kind_; }
  // Mip levels (1 for a parameter file) and the size of a level.
  int Levels() const { return static_cast<int>(levels_.size()); }
  int Width(int level) const { return levels_[ClampLevel(level)].width; }
  int Height(int level) const { return levels_[ClampLevel(level)].height; }

  // The BRDF f (1/sr, per channel) and the cosine-weighted rho = f wi.z.
  // (s, t) in [0, 1]^2 picks the nearest texel of `level` (both clamped to
  // the valid range); a parameter file ignores them.
  glm::dvec3 F(const glm::dvec3& wi, const glm::dvec3& wo, double s = 0.0,
               double t = 0.0, int level = 0) const noexcept {
    return Value(wi, wo, s, t, level, Quantity::kBrdf);
  }
  glm::dvec3 Rho(const glm::dvec3& wi, const glm::dvec3& wo, double s = 0.0,
                 double t = 0.0, int level = 0) const noexcept {
    return Value(wi, wo, s, t, level, Quantity::kCosineWeighted);
  }

 private:
  Material() = default;  // only through Load / FromParams: never empty

  struct Level {
    int width = 1, height = 1;
    std::vector<ModelParams> texels;  // y * width + x
  };

  // One parameter set, validated once at the boundary (models/evaluate.h
  // ValidateModel); messages start with `name`.
  static Level OneTexel(const ModelParams& params, const std::string& name);

  int ClampLevel(int level) const noexcept {
    const int last = static_cast<int>(levels_.size()) - 1;
    return level < 0 ? 0 : (level > last ? last : level);
  }
  glm::dvec3 Value(const glm::dvec3& wi, const glm::dvec3& wo, double s,
                   double t, int level, Quantity q) const noexcept;

  std::string kind_;
  std::vector<Level> levels_;
};

}  // namespace clothfit
