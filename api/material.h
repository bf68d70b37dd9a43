// The stable evaluation API for renderers: load a parameter file
// or a Lafortune parameter mip map once, then evaluate f or rho for
// (wi, wo) in a renderer's inner loop, in double (Material) or float
// (MaterialF), and sample wi given wo for a path tracer.
//
//   clothfit::Material m = clothfit::Material::Load("satin.json");
//   glm::dvec3 f = m.F(wi, wo);               // BRDF, 1/sr
//   glm::dvec3 rho = m.Rho(wi, wo, s, t, 2);  // mip map: texel (s, t), level 2
//   clothfit::MaterialF mf = clothfit::MaterialF::Load("satin.json");
//   glm::vec3 ff = mf.F(glm::vec3(wi), glm::vec3(wo));
//   clothfit::BsdfSampleT<double> b = m.Sample(wo, u1, u2);  // b.wi, b.pdf,
//   // b.weight = f |wi.z| / pdf; m.Pdf(wo, wi) for MIS
//
// Loading prepares what depends on the parameters alone (models/prepared.h:
// a cloth's sample frames, a texel's frame). A float material evaluates the
// thread, cloth and Lafortune models in float (within 1e-5 of double,
// relative to the larger of the value and a thousandth of the material's
// peak: docs/renderer.md), the slab and holes in double; its values are
// finite (saturated at the largest float).
//
// Directions are unit vectors in the surface frame (docs/formats.md: normal +z,
// warp/u along +x, weft/v along +y), both pointing away from the surface;
// for a thread file, in the thread frame (tangent +x, docs/models.md).
// Loading throws InputError (io/input_error.h) naming the file and the
// problem. Evaluation never throws, never allocates, and only reads the
// loaded data, so any number of threads may evaluate one Material at once.
// For a slab, f is the reflection or transmission BSDF (wi and wo on
// opposite sides: transmission); its direct transmission, and all of a
// holes layer's (which has no BSDF: F is 0), is what Sample returns as a
// delta sample (BsdfSampleT::delta).
#pragma once

#include <string>
#include <vector>

#include "models/evaluate.h"
#include "models/prepared.h"

namespace clothfit {

// How a texture map (a Lafortune parameter mip map) is looked up at
// (s, t) and level `lod`: the texel nearest to (s, t) on the level nearest
// to lod; bilinear interpolation of the 4 texels around (s, t) on that
// level (texel centres at (x + 0.5) / width; clamped at the edges); or
// trilinear: bilinear on levels floor(lod) and floor(lod) + 1, then linear
// between them. Interpolation blends the texels' values (f, rho, pdf):
// their parameters are not interpolated.
enum class TexelFilter { kNearest, kBilinear, kTrilinear };

// A direction sampled for a path tracer (MaterialT::Sample).
template <typename Real>
struct BsdfSampleT {
  glm::vec<3, Real> wi{Real(0), Real(0), Real(1)};  // unit
  // Per steradian (= Pdf(wo, wi)); for a delta sample, the probability of
  // having chosen it.
  Real pdf = Real(0);
  // rho(wi, wo) / pdf = f |wi.z| / pdf per channel (a delta sample: its
  // direct transmittance / pdf); 0 where pdf is 0. Finite.
  glm::vec<3, Real> weight{Real(0), Real(0), Real(0)};
  // Direct transmission (slab, holes): wi = -wo exactly, a direction F and
  // Pdf do not describe (multiple importance sampling must skip it).
  bool delta = false;
};

// Real: double or float (the two instantiations, Material and MaterialF).
template <typename Real>
class MaterialT {
 public:
  // A parameter file of any model (docs/formats.md: thread, cloth, lafortune,
  // slab; holes when the file holds its mask's tile, as `clothfit fit --model
  // holes` and `clothfit holes tile` write it) or, for a path ending in
  // ".exr", a parameter mip map written by
  // `clothfit fit --model lafortune` on a table with s,t columns, looked
  // up with `filter`.
  static MaterialT Load(const std::string& path,
                        TexelFilter filter = TexelFilter::kNearest);
  // A parameter set already in memory (e.g. a preset, models/presets.h).
  // Throws InputError when a field is out of range.
  static MaterialT FromParams(const ModelParams& params);

  // "thread" | "cloth" | "lafortune" | "slab" | "holes" |
  // "lafortune_mipmap".
  const std::string& Kind() const { return kind_; }
  // Mip levels (1 for a parameter file) and the size of a level.
  int Levels() const { return static_cast<int>(levels_.size()); }
  int Width(int level) const { return levels_[ClampLevel(level)].width; }
  int Height(int level) const { return levels_[ClampLevel(level)].height; }

  // The BRDF f (1/sr, per channel) and the cosine-weighted rho = f |wi.z|.
  // (s, t) in [0, 1]^2 and the mip level `lod` (0 the finest) pick texels
  // by the material's TexelFilter (all clamped to the valid range); a
  // parameter file ignores them.
  using Vec = glm::vec<3, Real>;
  Vec F(const Vec& wi, const Vec& wo, Real s = Real(0), Real t = Real(0),
        Real lod = Real(0)) const noexcept {
    return Value(wi, wo, s, t, lod, Quantity::kBrdf);
  }
  Vec Rho(const Vec& wi, const Vec& wo, Real s = Real(0), Real t = Real(0),
          Real lod = Real(0)) const noexcept {
    return Value(wi, wo, s, t, lod, Quantity::kCosineWeighted);
  }

  // Importance sampling (models/model_sampling.h): wi given wo from two
  // uniform numbers in [0, 1), at the texels F uses. Every model samples
  // the side(s) its F covers (cloth, Lafortune and sheen reflect, a thread
  // scatters to both sides, a slab reflects and transmits); a slab's
  // direct transmission and a holes layer are delta samples.
  BsdfSampleT<Real> Sample(const Vec& wo, Real u1, Real u2, Real s = Real(0),
                           Real t = Real(0), Real lod = Real(0)) const noexcept;
  // The density per steradian with which Sample returns wi (its
  // continuous part: over the sphere it integrates to 1 minus the
  // probability of a delta sample).
  Real Pdf(const Vec& wo, const Vec& wi, Real s = Real(0), Real t = Real(0),
           Real lod = Real(0)) const noexcept;
  TexelFilter Filter() const { return filter_; }

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
  // The texels a lookup at (s, t, lod) blends and their weights (summing
  // to 1): up to 8 (trilinear).
  struct Taps {
    int count = 0;
    const PreparedModel<Real>* texel[8];
    Real weight[8];
  };
  Taps Lookup(Real s, Real t, Real lod) const noexcept;
  void AddLevel(int level, Real s, Real t, Real weight,
                Taps* taps) const noexcept;
  Vec Value(const Vec& wi, const Vec& wo, Real s, Real t, Real lod,
            Quantity q) const noexcept;

  std::string kind_;
  TexelFilter filter_ = TexelFilter::kNearest;
  std::vector<Level> levels_;
};

extern template class MaterialT<double>;
extern template class MaterialT<float>;
using Material = MaterialT<double>;
using MaterialF = MaterialT<float>;

}  // namespace clothfit
