// Holes wider than one texel: the thesis's own future-work fix
// (David-Babin 2022, Ch. 5: "store the distance ... of a transparent texel
// to the closest opaque texel for each direction"; the limitation of
// Fig. 4.8/4.9), in a form that sums linearly over mip blocks.
//
// Distances. For a transparent texel and each of 8 directions d (steps
// (1,0), (0,1), (-1,0), (0,-1) and the diagonals (1,1), (-1,1), (-1,-1),
// (1,-1)) the run k_d is the number of transparent texels stepped over
// before the first opaque one (k = 0: the neighbour is opaque). Runs of
// kDistanceBins or more count as "no opaque texel within reach".
//
// Linearly filterable form. A texel stores, per direction, the cumulative
// indicators C_d[j] = [k_d <= j], j = 0..kDistanceBins-1 (C_d[0] is the
// wall of Algorithm 3.1); a mip level sums them, so C_d[j] of a block
// counts its texels with k_d <= j. At level 0 the indicators give k_d back
// exactly. A diagonal run is stored only where it is shorter than both
// axial runs of its quadrant (an opaque texel inside the "free rectangle"
// that the axial runs span; in a rectangular hole the diagonal run equals
// the shorter axial run and adds nothing).
//
// Evaluation (rx, ry >= 0; other quadrants mirror it, u = |rx|, v = |ry|).
// 1D: a ray entering at x0 in [0, 1] meets the wall k texels away when
// x0 + u > 1 + k, a fraction clamp(u - k, 0, 1) of the texel, so
//   S_x = sum_j (C_E[j] - C_E[j-1]) clamp(u - j, 0, 1)     (exact in 1D)
// and S_y likewise with C_N and v. A diagonal obstacle m texels away (the
// square [1+m, 2+m]^2) occludes the starts p whose segment p -> p + r meets
// it, the part of [0, 1]^2 inside the square swept by -r (a hexagon,
// DiagonalHitArea); S_d = sum_m (C_NE[m] - C_NE[m-1]) DiagonalHitArea(m).
// Within a texel the three are treated as independent:
//   free = (1 - a)(1 - b)(1 - c),
// which is exact for a texel inside a rectangular hole (a ray stays free
// iff it ends inside the rectangle, and the two conditions are
// independent). Over a block of N transparent texels the fractions are
// replaced by their block means, M(r) = N (1 - (1 - S_x/N)(1 - S_y/N)
// (1 - S_d/N)); an aligned block meets a rectangular hole in a rectangle,
// where the block means are again independent, so rectangular holes stay
// exact at every level whose blocks each overlap one hole (and over whole
// periods of identical holes).
//
// The extension keeps Algorithm 3.1 where it is exact and adds what lies
// beyond the clamp: O_ext(r) = O_3.1(r) + M(r) - M(clamp(r)). For
// |rx|, |ry| <= 1 it is Algorithm 3.1; it is continuous in r; M grows with
// |rx| and |ry|, so the increment is never negative.
#pragma once

#include <array>

#include "models/holes.h"

namespace clothfit {

// Runs stored per direction (reach of the extension: kDistanceBins texels
// beyond the neighbour).
inline constexpr int kDistanceBins = 8;
enum Direction8 : int {
  kEast = 0,       // +x
  kNorth = 1,      // +y
  kWest = 2,       // -x
  kSouth = 3,      // -y
  kNorthEast = 4,  // (+x, +y)
  kNorthWest = 5,  // (-x, +y)
  kSouthWest = 6,  // (-x, -y)
  kSouthEast = 7,  // (+x, -y)
};
inline constexpr int kDirections8 = 8;
inline constexpr int kDistanceChannels = kDirections8 * kDistanceBins;

// Step of direction d.
inline void Direction8Step(int d, int* dx, int* dy) {
  static const int kDx[kDirections8] = {1, 0, -1, 0, 1, -1, -1, 1};
  static const int kDy[kDirections8] = {0, 1, 0, -1, 1, 1, -1, -1};
  *dx = kDx[d];
  *dy = kDy[d];
}

inline const char* Direction8Name(int d) {
  static const char* const kNames[kDirections8] = {"E",  "N",  "W",  "S",
                                                   "NE", "NW", "SW", "SE"};
  return kNames[d];
}

// The cumulative run counts of a texel or block: cumulative[d *
// kDistanceBins + j] = C_d[j].
struct HoleDistanceTexel {
  std::array<double, kDistanceChannels> cumulative{};
};

// sum_j (C[j] - C[j-1]) clamp(u - j, 0, 1) for u >= 0.
template <typename T>
T RunOcclusion(const double* cumulative, const T& u) {
  T sum = T(0.0);
  double previous = 0.0;
  for (int j = 0; j < kDistanceBins; ++j) {
    const double count = cumulative[j] - previous;
    previous = cumulative[j];
    if (!(u > T(j))) break;
    if (count != 0.0) sum += T(count) * Min(u - T(j), T(1.0));
  }
  return sum;
}

namespace holes_internal {

// Keeps the part of the convex polygon in[0..n) with sign * (p[axis] -
// bound) >= 0 (Sutherland-Hodgman, one edge); returns the new count.
template <typename T>
int ClipPolygon(const Vec2<T>* in, int n, int axis, double bound, double sign,
                Vec2<T>* out) {
  int m = 0;
  for (int i = 0; i < n; ++i) {
    const Vec2<T>& p = in[i];
    const Vec2<T>& q = in[(i + 1) % n];
    const T dp = T(sign) * (p[axis] - T(bound));
    const T dq = T(sign) * (q[axis] - T(bound));
    const bool p_in = dp >= T(0.0);
    const bool q_in = dq >= T(0.0);
    if (p_in) out[m++] = p;
    if (p_in != q_in) {
      const T s = dp / (dp - dq);
      out[m++] = Vec2<T>(p.x + (q.x - p.x) * s, p.y + (q.y - p.y) * s);
    }
  }
  return m;
}

}  // namespace holes_internal

// Area of the starts p in [0, 1]^2 whose segment p -> p + (u, v) (u, v >=
// 0) meets the square [a, a+1]^2, a = 1 + m: the unit square clipped by the
// square swept by -(u, v), the hexagon below (counter-clockwise).
template <typename T>
T DiagonalHitArea(int m, const T& u, const T& v) {
  if (!(u > T(m) && v > T(m))) return T(0.0);
  const double a = 1.0 + m;
  Vec2<T> buffer_a[16], buffer_b[16];
  buffer_a[0] = Vec2<T>(T(a) - u, T(a) - v);
  buffer_a[1] = Vec2<T>(T(a + 1.0) - u, T(a) - v);
  buffer_a[2] = Vec2<T>(T(a + 1.0), T(a));
  buffer_a[3] = Vec2<T>(T(a + 1.0), T(a + 1.0));
  buffer_a[4] = Vec2<T>(T(a), T(a + 1.0));
  buffer_a[5] = Vec2<T>(T(a) - u, T(a + 1.0) - v);
  int n = 6;
  n = holes_internal::ClipPolygon(buffer_a, n, 0, 1.0, -1.0, buffer_b);
  n = holes_internal::ClipPolygon(buffer_b, n, 1, 1.0, -1.0, buffer_a);
  n = holes_internal::ClipPolygon(buffer_a, n, 0, 0.0, 1.0, buffer_b);
  n = holes_internal::ClipPolygon(buffer_b, n, 1, 0.0, 1.0, buffer_a);
  T twice_area = T(0.0);
  for (int i = 0; i < n; ++i) {
    const Vec2<T>& p = buffer_a[i];
    const Vec2<T>& q = buffer_a[(i + 1) % n];
    twice_area += p.x * q.y - q.x * p.y;
  }
  return T(0.5) * twice_area;
}

// M(r): the occluded count of the free-rectangle model (see the top of the
// file) for the texel or block, in texel areas.
template <typename T>
T RunModelOccluded(const HoleTexel& t, const HoleDistanceTexel& d,
                   const Vec2<T>& r) {
  const double transparent = t.texels - t.counts[kOpaques];
  if (!(transparent > 0.0)) return T(0.0);
  const bool east = r.x >= T(0.0), north = r.y >= T(0.0);
  const T u = east ? r.x : -r.x;
  const T v = north ? r.y : -r.y;
  const int dir_x = east ? kEast : kWest;
  const int dir_y = north ? kNorth : kSouth;
  const int diagonal = east ? (north ? kNorthEast : kSouthEast)
                            : (north ? kNorthWest : kSouthWest);
  const double* c = d.cumulative.data();
  const T s_x = RunOcclusion(c + dir_x * kDistanceBins, u);
  const T s_y = RunOcclusion(c + dir_y * kDistanceBins, v);
  T s_d = T(0.0);
  double previous = 0.0;
  for (int m = 0; m < kDistanceBins; ++m) {
    const double count = c[diagonal * kDistanceBins + m] - previous;
    previous = c[diagonal * kDistanceBins + m];
    if (count != 0.0) s_d += T(count) * DiagonalHitArea(m, u, v);
  }
  const double inv = 1.0 / transparent;
  const T free_fraction = Clamp(T(1.0) - s_x * T(inv), T(0.0), T(1.0)) *
                          Clamp(T(1.0) - s_y * T(inv), T(0.0), T(1.0)) *
                          Clamp(T(1.0) - s_d * T(inv), T(0.0), T(1.0));
  return T(transparent) * (T(1.0) - free_fraction);
}

// The extension's ratios: O_ext = O_3.1(r) + M(r) - M(clamp(r)), at most
// the transparent count.
template <typename T>
HoleRatiosT<T> ExtendedRatios(const HoleTexel& t, const HoleDistanceTexel& d,
                              const Vec2<T>& r) {
  const Vec2<T> clamped(Clamp(r.x, T(-1.0), T(1.0)),
                        Clamp(r.y, T(-1.0), T(1.0)));
  const double transparent = t.texels - t.counts[kOpaques];
  const T occluded = Min(OccludedCount31(t, r) + RunModelOccluded(t, d, r) -
                             RunModelOccluded(t, d, clamped),
                         T(Max(transparent, 0.0)));
  HoleRatiosT<T> out;
  const double inv_texels = 1.0 / t.texels;
  out.opaque = T(t.counts[kOpaques] * inv_texels);
  out.occluded = occluded * T(inv_texels);
  out.transparent = T(1.0) - out.occluded - out.opaque;
  return out;
}

}  // namespace clothfit
