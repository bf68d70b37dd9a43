// The stable evaluation API for renderers: load a parameter file
// or a Lafortune parameter mip map once, then evaluate f or rho for
// (wi, wo) in a renderer's inner loop, in double (Material) or float
// (MaterialF).
//
//   clothfit::Material m = clothfit::Material::Load("satin.json");
//   glm::dvec3 f = m.F(wi, wo);               // BRDF, 1/sr
//   glm::dvec3 rho = m.Rho(wi, wo, s, t, 2);  // mip map: texel (s, t), level 2
//   clothfit::MaterialF mf = clothfit::MaterialF::Load("satin.json");
//   glm::vec3 ff = mf.F(glm::vec3(wi), glm::vec3(wo));
//
// Loading prepares what depends on the parameters alone (models/prepared.h:
// a cloth's sample frames, a texel's frame). A float material evaluates the
// thread, cloth and Lafortune models in float (within 1e-5 of double,
// relative to the larger of the value and a thousandth of the material's
// peak: docs/renderer.md), the slab and holes in double; its values are
// finite (saturated at the largest float).
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
#include "models/prepared.h"

namespace clothfit {

// Real: double or float (the two instantiations, Material and MaterialF).
template <typename Real>
class MaterialT {
 public:
  // A parameter file of any model (SPEC §4: thread, cloth, lafortune, slab)
  // or, for a path ending in ".exr", a parameter mip map written by
  // `clothfit fit --model lafortune` on a table with s,t columns.
  static MaterialT Load(const std::string& path);
  // A parameter set already in memory (e.g. a preset, models/presets.h).
  // Throws InputError when a field is out of range.
  static MaterialT FromParams(const ModelParams& params);

  // "thread" | "cloth" | "lafortune" | "slab" | "lafortune_mipmap".
  const std::string& Kind() const { return kind_; }
  // Mip levels (1 for a parameter file) and the size of a level.
  int Levels() const { return static_cast<int>(levels_.size()); }
  int Width(int level) const { return levels_[ClampLevel(level)].width; }
  int Height(int level) const { return levels_[ClampLevel(level)].height; }

  // The BRDF f (1/sr, per channel) and the cosine-weighted rho = f wi.z.
  // (s, t) in [0, 1]^2 picks the nearest texel of `level` (both clamped to
  // the valid range); a parameter file ignores them.
  using Vec = glm::vec<3, Real>;
  Vec F(const Vec& wi, const Vec& wo, Real s = Real(0), Real t = Real(0),
        int level = 0) const noexcept {
    return Value(wi, wo, s, t, level, Quantity::kBrdf);
  }
  Vec Rho(const Vec& wi, const Vec& wo, Real s = Real(0), Real t = Real(0),
          int level = 0) const noexcept {
    return Value(wi, wo, s, t, level, Quantity::kCosineWeighted);
  }

 private:
  MaterialT() = default;  // only through Load / FromParams: never empty

  struct Level {
    int width = 1, height = 1;
    std::vector<PreparedModel<Real>> texels;  // y * width + x
  };

  // One parameter set, validated once at the boundary (models/evaluate.h
  // ValidateModel); messages start with `name`.
  static Level OneTexel(const ModelParams& params, const std::string& name);

  int ClampLevel(int level) const noexcept {
    const int last = static_cast<int>(levels_.size()) - 1;
    return level < 0 ? 0 : (level > last ? last : level);
  }
  Vec Value(const Vec& wi, const Vec& wo, Real s, Real t, int level,
            Quantity q) const noexcept;

  std::string kind_;
  std::vector<Level> levels_;
};

extern template class MaterialT<double>;
extern template class MaterialT<float>;
using Material = MaterialT<double>;
using MaterialF = MaterialT<float>;

}  // namespace clothfit
