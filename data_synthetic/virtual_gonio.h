// A virtual gonioreflectometer over woven and knitted micro-geometry, in
// the spirit of Daubert et al. 2001, Section 4: a procedural height field
// of threads (one tile, repeated), an s x s grid of sampling points (texels)
// on it, and an n x n sampling of the hemisphere for lights and views. For
// each texel and each (light, view) pair: ray-cast visibility of the
// surface from the viewer (holes between threads -> alpha 0), shadowing of
// the light, and a local shading (Lambert + a glossy term around the thread
// tangent, coloured threads). Deterministic from a seed.
//
// Geometry (tile [0,1)^2, periodic). Warp threads run along +x, weft threads
// along +y (docs/formats.md). A thread's cross-section is a half-ellipse:
// half-width w on the ground plane, half-height r_z above its centre line,
// whose height undulates between crossings (over: +A, under: -A, A = 0.55 r_z,
// cosine interpolation between crossings). The surface is the highest thread
// over (x, y); where no thread lies there is a hole and the viewer sees
// through.
//   plain: 2 warps x 2 wefts per tile, over/under at every crossing.
//   satin: 5 x 5 per tile, 5-harness warp-faced satin (move 2): each warp
//          floats over 4 wefts and passes under 1.
//   knit:  stockinette-like: 2 wales of 2 loop legs each (threads along y
//          whose centre line is bent sinusoidally, forming V's) rising
//          between and diving at the course lines, where one course thread
//          along x per course (2 per tile) holds them (the loop heads).
//          Legs use the weft colour, course threads the warp colour.
// thread_radius and gap are given for a thread pitch of 0.5 (the plain
// weave's 2 threads per tile) and scaled with the pattern's pitch (satin:
// x 0.4, knit: x 0.5): r_z = thread_radius, w = (pitch - gap) / 2, so the
// defaults give circular cross-sections and gap = 0 closes every hole.
//
// Directions: n x n strata in (cos theta, phi), cos theta = c0 + (1 - c0)
// (i + 0.5) / n with c0 = cos 85 deg, phi = 2 pi (j + 0.5) / n; direction
// index i * n + j. The same set serves for lights and views.
//
// Measurement (as in the paper's Fig. 2): the texel's k x k jittered sample
// points lie on the top face of the tile's bounding box; each is projected
// along the view direction onto the micro-geometry (the ray travels along
// -v from z = max height). A ray that falls through a hole adds 0; one that
// hits is shaded towards the light with a shadow ray. Per (texel, view,
// light): value = mean over the k x k rays of the shaded radiance (so holes
// darken the value), alpha = fraction of the rays that hit a thread (the
// same for every light). Each texel's rows carry its average normal (the
// normalised sum of the hit normals over all its views and rays), the frame
// the paper fits the texel's lobes in.
//
// Shading at a hit with normal n, thread tangent t, thread colour c (radiance
// per unit irradiance, i.e. the cosine-weighted quantity rho):
//   rho = V(l) max(n.l, 0) [(1 - g) c / pi + g tint sin(t, h)^p / B]
// with g = glossy in [0, 1], h = normalize(l + v), p = 32, tint = (1 + c) /
// 2, V(l) = 1 unless the shadow ray towards l meets a thread, and B =
// 1.4991 the largest albedo of the band sin(t, h)^32 on a facet: the
// shading's directional albedo is at most (1 - g) c + g tint <= 1, so the
// measured texels conserve energy (their fits must too, fitting/energy.h).
// No interreflections, no ambient.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "io/table.h"

namespace clothfit {

enum class WeavePattern { kPlain, kSatin, kKnit };

struct VirtualGonioOptions {
  WeavePattern pattern = WeavePattern::kPlain;
  int texels = 8;      // s: the tile is sampled at s x s texels
  int directions = 8;  // n: n x n hemisphere directions for lights and views
  uint64_t seed = 1;   // jitter of the sampling, thread colour variation
  double thread_radius = 0.22;  // in tile units (a tile holds 2 x 2 crossings)
  double gap = 0.06;            // space between threads (holes), tile units
  double glossy = 0.35;         // weight of the glossy term, [0, 1]
  int supersample = 2;          // rays per texel per direction (k x k)
  // Resolution of the precomputed height-field grid the rays march through
  // (grid x grid samples of the tile, bilinear lookup). >= 16.
  int grid = 512;
  // Worker threads (texels are shared out among them); 0 =
  // std::thread::hardware_concurrency(). The result does not depend on it.
  int threads = 0;
  // Called with the texels measured so far and their count, from one
  // thread at a time (for a progress line); may be empty.
  std::function<void(int done, int total)> progress;
};

// The measured table: quantity cosine_weighted (radiance per unit
// irradiance), one row per (texel, light, view) with s,t, r,g,b and alpha
// (the fraction of the texel's rays that hit the surface from the view). A
// view ray that finds a hole gives 0 radiance and lowers alpha. The frame
// is the surface frame (normal +z, warp +x). Directions as unit vectors
// (wi = light, wo = view), sigma = weight = 1. Row order: texel-major
// (t, then s), then view, then light, so row
//   ((t * s_count + s) * n^2 + view) * n^2 + light.
// Metadata: sample (a one-line description), pattern, texels, directions,
// seed, supersample, thread_radius, gap, glossy, row_order.
// Throws InputError for options out of range: texels, directions,
// supersample < 1; grid < 16; threads < 0; thread_radius <= 0; gap outside
// [0, 0.5); glossy < 0; more than kMaxVirtualGonioRows rows. Memory: the
// rows dominate (s^2 n^4 TableRows; the paper's 32 x 32 texels, n = 8
// make 4.2 M rows, about 0.75 GB).
// 12 M rows hold scripts/scale.sh's 50 x 50 texels x 64 x 64 directions
// (10.24 M); a row costs ~530 bytes while the table is made and written.
inline constexpr double kMaxVirtualGonioRows = 12e6;
MeasurementTable MeasureVirtualGonio(const VirtualGonioOptions& options);

// "plain" | "satin" | "knit"; false for an unknown name.
bool ParseWeavePattern(const std::string& name, WeavePattern* pattern);

// The inverse: "plain" | "satin" | "knit".
const char* WeavePatternName(WeavePattern pattern);

}  // namespace clothfit
