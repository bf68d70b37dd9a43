#include "data_synthetic/holes_truth.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "data_synthetic/synthetic_table.h"

namespace clothfit {
namespace {

int Wrap(int64_t i, int n) {
  const int64_t k = i % n;
  return static_cast<int>(k < 0 ? k + n : k);
}

}  // namespace

RayOutcome TraceHoleRay(const Mask& mask, const glm::dvec2& p,
                        const glm::dvec2& r) {
  const int w = mask.width, h = mask.height;
  const double fx = std::floor(p.x), fy = std::floor(p.y);
  int ix = Wrap(static_cast<int64_t>(fx), w);
  int iy = Wrap(static_cast<int64_t>(fy), h);
  const uint8_t* opaque = mask.opaque.data();
  if (opaque[static_cast<size_t>(iy) * w + ix]) return RayOutcome::kOpaque;
  // Amanatides-Woo: t_max_* is the ray parameter (0..1 over the descent) of
  // the next crossing of a vertical / horizontal texel edge.
  constexpr double kNever = std::numeric_limits<double>::infinity();
  const int step_x = r.x > 0.0 ? 1 : -1;
  const int step_y = r.y > 0.0 ? 1 : -1;
  double t_max_x = r.x > 0.0   ? (fx + 1.0 - p.x) / r.x
                   : r.x < 0.0 ? (p.x - fx) / -r.x
                               : kNever;
  double t_max_y = r.y > 0.0   ? (fy + 1.0 - p.y) / r.y
                   : r.y < 0.0 ? (p.y - fy) / -r.y
                               : kNever;
  const double t_delta_x = r.x != 0.0 ? 1.0 / std::abs(r.x) : kNever;
  const double t_delta_y = r.y != 0.0 ? 1.0 / std::abs(r.y) : kNever;
  for (;;) {
    if (t_max_x <= t_max_y) {  // x first at a corner
      if (t_max_x >= 1.0) break;
      t_max_x += t_delta_x;
      ix += step_x;
      if (ix == w) ix = 0;
      if (ix < 0) ix = w - 1;
    } else {
      if (t_max_y >= 1.0) break;
      t_max_y += t_delta_y;
      iy += step_y;
      if (iy == h) iy = 0;
      if (iy < 0) iy = h - 1;
    }
    if (opaque[static_cast<size_t>(iy) * w + ix]) return RayOutcome::kOccluded;
  }
  return RayOutcome::kTransparent;
}

Footprint BlockFootprint(int x0, int y0, int x1, int y1,
                         int samples_per_texel) {
  Footprint f;
  f.origin = glm::dvec2(x0, y0);
  f.edge_u = glm::dvec2(x1 - x0, 0.0);
  f.edge_v = glm::dvec2(0.0, y1 - y0);
  f.samples_u = (x1 - x0) * samples_per_texel;
  f.samples_v = (y1 - y0) * samples_per_texel;
  return f;
}

HoleRatios HoleTruth(const Mask& mask, const glm::dvec2& r,
                     const Footprint& footprint) {
  int64_t counts[3] = {0, 0, 0};
  for (int j = 0; j < footprint.samples_v; ++j) {
    const double b = (j + 0.5) / footprint.samples_v;
    for (int i = 0; i < footprint.samples_u; ++i) {
      const double a = (i + 0.5) / footprint.samples_u;
      const glm::dvec2 p =
          footprint.origin + a * footprint.edge_u + b * footprint.edge_v;
      ++counts[static_cast<int>(TraceHoleRay(mask, p, r))];
    }
  }
  const double n = static_cast<double>(footprint.samples_u) *
                   static_cast<double>(footprint.samples_v);
  HoleRatios out;
  out.opaque = counts[static_cast<int>(RayOutcome::kOpaque)] / n;
  out.occluded = counts[static_cast<int>(RayOutcome::kOccluded)] / n;
  out.transparent = counts[static_cast<int>(RayOutcome::kTransparent)] / n;
  return out;
}

HoleRatios HoleTruthTile(const Mask& mask, const glm::dvec2& r,
                         int samples_per_texel) {
  return HoleTruth(
      mask, r,
      BlockFootprint(0, 0, mask.width, mask.height, samples_per_texel));
}

Footprint TileFootprint(const Mask& mask, int64_t rays) {
  Footprint f = BlockFootprint(0, 0, mask.width, mask.height, 1);
  const double aspect = static_cast<double>(mask.width) / mask.height;
  f.samples_u =
      std::max(1, static_cast<int>(std::lround(std::sqrt(rays * aspect))));
  f.samples_v = std::max(
      1,
      static_cast<int>(std::lround(static_cast<double>(rays) / f.samples_u)));
  return f;
}

Mask SquareHoleMask(int hole, int bar) {
  Mask mask;
  mask.width = mask.height = hole + bar;
  mask.opaque.resize(static_cast<size_t>(mask.width) * mask.height);
  for (int y = 0; y < mask.height; ++y) {
    for (int x = 0; x < mask.width; ++x) {
      mask.opaque[static_cast<size_t>(y) * mask.width + x] =
          x < hole && y < hole ? 0 : 1;
    }
  }
  return mask;
}

Mask RandomMask(int width, int height, double opaque_fraction, uint64_t seed) {
  Random random(seed);
  Mask mask;
  mask.width = width;
  mask.height = height;
  mask.opaque.resize(static_cast<size_t>(width) * height);
  for (uint8_t& v : mask.opaque) v = random.Uniform() < opaque_fraction;
  return mask;
}

}  // namespace clothfit
