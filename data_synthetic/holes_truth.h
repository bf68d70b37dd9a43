// Ground truth for semi-transparent textures with thickness (docs/models.md):
// each view ray is traced exactly through the tiled texel grid (the 2D DDA
// of Amanatides and Woo 1987, as in David-Babin 2022 §4.2, Fig. 4.10)
// against the columns of height h, and the outcomes are averaged over a
// pixel footprint. Any offset r (|rx|, |ry| unbounded) and any view
// direction.
//
// A ray lands at p on the top of the layer. On an opaque texel it is
// "opaque"; otherwise it descends and travels p -> p + r (t in [0, 1]); it
// is "occluded" if any texel it enters on the way is opaque, else
// "transparent". Rays through a texel corner (measure zero) step in x
// first.
//
// Also synthetic masks for tests, charts and benchmarks.
#pragma once

#include <cstdint>
#include <glm/vec2.hpp>
#include <vector>

#include "io/mask_io.h"
#include "models/holes.h"

namespace clothfit {

enum class RayOutcome { kOpaque, kOccluded, kTransparent };

// The outcome of the ray landing at p (texels; any reals, the mask tiles).
RayOutcome TraceHoleRay(const Mask& mask, const glm::dvec2& p,
                        const glm::dvec2& r);

// A pixel footprint in texture space: the parallelogram origin + a edge_u
// + b edge_v, a, b in [0, 1), sampled at the centres of a samples_u x
// samples_v grid.
struct Footprint {
  glm::dvec2 origin{0.0};
  glm::dvec2 edge_u{1.0, 0.0};
  glm::dvec2 edge_v{0.0, 1.0};
  int samples_u = 1, samples_v = 1;
};

// The base texels [x0, x1) x [y0, y1) with samples_per_texel^2 rays per
// texel (a mip block, or the whole tile).
Footprint BlockFootprint(int x0, int y0, int x1, int y1, int samples_per_texel);

// Fractions of the footprint's rays with each outcome. A regular grid of n
// samples per texel side integrates each texel's occluded region, a
// polygon, with an error of about (its interior boundary's extent) / (2 n)
// per boundary segment: at most 2 / n per texel for |rx|, |ry| <= 1 (three
// segments; see docs/holes.md).
HoleRatios HoleTruth(const Mask& mask, const glm::dvec2& r,
                     const Footprint& footprint);

// The whole tile: BlockFootprint(0, 0, W, H, samples_per_texel).
HoleRatios HoleTruthTile(const Mask& mask, const glm::dvec2& r,
                         int samples_per_texel);

// The whole tile with about `rays` rays on a grid whose spacing need not
// divide a texel (large masks with fewer rays than texels still sample
// every position within a texel, not only texel centres).
Footprint TileFootprint(const Mask& mask, int64_t rays);

// Square holes of hole x hole texels between bars `bar` texels wide: one
// period ((hole + bar) square), e.g. the thesis's mosquito net (5, 1).
Mask SquareHoleMask(int hole, int bar);

// Texels opaque with probability `opaque_fraction`, reproducibly from seed.
Mask RandomMask(int width, int height, double opaque_fraction, uint64_t seed);

}  // namespace clothfit
