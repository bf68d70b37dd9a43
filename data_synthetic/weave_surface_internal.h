// The woven micro-geometry of the virtual gonioreflectometer
// (data_synthetic/virtual_gonio.h): threads over a tile, the surface they
// make, its height grid, and the view and shadow rays marched against it.
// For data_synthetic/ only (not installed).
#pragma once

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <vector>

#include "data_synthetic/synthetic_table.h"
#include "data_synthetic/virtual_gonio.h"

namespace clothfit {
namespace weave_internal {

// Exponent of the glossy (Kajiya-Kay-like) lobe.
inline constexpr double kGlossyExponent = 32.0;
// The largest albedo of the unnormalised band, the integral over l of
// max(n.l, 0) sin(t, h)^32 on a flat facet (n = z, t = x): 1.4991, at the
// view along the normal (tests/virtual_gonio_test.cc integrates it). The
// shading divides the band by it, so that the band's albedo is at most 1.
inline constexpr double kGlossyBandAlbedo = 1.4991;
// March step, relative to the smaller of the thread's half-width and
// half-height; intersections are then refined by bisection.
inline constexpr double kStepFraction = 0.08;
inline constexpr int kBisections = 14;

// The thread pitch the options' thread_radius and gap refer to.
inline constexpr double kReferencePitch = 0.5;

// One thread over the tile. `along_x` threads (warp) run along x at rest
// position y = rest (and vice versa for weft). The along-coordinate u is x
// for warp, y for weft; the across-coordinate p the other one.
//   centre line across:  p_c(u) = rest + bend * cos(2 pi freq u)
//   centre line height:  crossings.empty() ? z0 + z1 cos(2 pi freq u)
//                        : cosine interpolation of crossings[i] placed at
//                          u_i = (i + 0.5) / crossings.size()
struct Thread {
  bool along_x = true;
  double rest = 0.0;
  double bend = 0.0;
  double freq = 0.0;
  double z0 = 0.0;
  double z1 = 0.0;
  std::vector<double> crossings;
  double half_width = 0.1;   // w
  double half_height = 0.1;  // r_z
  glm::dvec3 colour{0.5};
};

struct ThreadSample {
  double height = 0.0;       // surface height of the thread at (x, y)
  double distance = 0.0;     // distance from the centre line / half-width
  glm::dvec2 gradient{0.0};  // (dz/dx, dz/dy) of that surface
  glm::dvec3 tangent{1.0, 0.0, 0.0};
};

// The threads of one tile of the pattern.
std::vector<Thread> BuildThreads(const VirtualGonioOptions& options,
                                 Random* random);

// The surface point above (x, y): the highest thread whose footprint
// contains it. `covered` is false in a hole; `thread` is then the nearest
// thread (smallest relative distance), evaluated at its clamped edge.
struct SurfacePoint {
  bool covered = false;
  int thread = 0;
  ThreadSample sample;
};

SurfacePoint EvaluateSurface(const std::vector<Thread>& threads, double x,
                             double y);

// The surface sampled at grid x grid lattice points (i / grid, j / grid),
// periodic, with bilinear lookup. Holes are stored below `floor`, the level
// under which a descending ray can no longer meet anything.
class HeightGrid {
 public:
  HeightGrid(const std::vector<Thread>& threads, int n);

  // Bilinear, periodic.
  double Height(double x, double y) const;

  double floor() const { return floor_; }
  double top() const { return top_; }

 private:
  int n_;
  std::vector<double> z_;
  double floor_ = 0.0;
  double top_ = 0.0;
};

// Marches the view ray origin + tau * dir (dir.z < 0) down until it meets
// the surface (true, *hit = the refined intersection) or drops below the
// floor through a hole (false).
bool MarchView(const HeightGrid& grid, const glm::dvec3& origin,
               const glm::dvec3& dir, double step, glm::dvec3* hit);

// True when the ray from `from` towards `dir` (dir.z > 0) meets the surface
// before it rises above the tallest thread. The ray starts a small distance
// off the surface (it begins exactly on the bilinear surface).
bool Shadowed(const HeightGrid& grid, const glm::dvec3& from,
              const glm::dvec3& dir, double step);

}  // namespace weave_internal
}  // namespace clothfit
