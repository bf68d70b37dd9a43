// Semi-transparent texture with thickness (David-Babin 2022, §3.2-3.4 and
// Algorithm 3.1; docs/models.md), templated on the scalar type so that the same
// code evaluates double and Ceres Jets.
//
// A binary mask of opaque and transparent texels tiles the plane; opaque
// texels are columns of height h (in texel widths). Texel (x, y) is column
// x, row y of the mask image; +x is "right", +y (the next image row) "top".
// A view ray that lands on a transparent texel descends through the hole
// and travels r = (rx, ry) texels sideways on the way down
// (rx = -h wo.x / |wo.z|, ry = -h wo.y / |wo.z|, ViewOffset). It is
// occluded when it meets a column's wall.
//
// Derivation of Algorithm 3.1 (for rx, ry >= 0; the other quadrants
// mirror it). A ray entering the texel at (x0, y0) in [0, 1]^2 crosses
// x = 1 when x0 > 1 - rx and y = 1 when y0 > 1 - ry. Starts that cross only
// x = 1 (area rx - rx ry) meet the right neighbour R, only y = 1 (area
// ry - rx ry) the top neighbour U; starts that cross both (area rx ry) meet
// R then the diagonal D (half of them, those with (1 - x0)/rx < (1 - y0)/ry)
// or U then D (the other half). With R, U, D in {0, 1} (1 = opaque) the
// occluded area is
//   R (rx - rx ry) + U (ry - rx ry) + rx ry/2 (max(R, D) + max(U, D))
//   = R (rx - rx ry/2) + U (ry - rx ry/2) + rx ry/2 D (2 - R - U),
// exactly the thesis's O with H = R (walls), V = U and the triangle count
// D (2 - R - U) (§3.4: where the diagonal neighbour is opaque, the number of
// the two texels between them that are not opaque). O is linear in these
// counts, so a mip level that sums them over a block of T texels gives the
// block's exact occluded area O / T (§3.4, "the sum of integers is
// linear"). The clamp |rx|, |ry| <= 1 is the thesis's: rays that travel
// further than one texel can meet walls beyond the direct neighbours
// (Fig. 4.8), which models/holes_distance.h handles.
#pragma once

#include <array>
#include <cmath>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "models/math.h"
#include "models/params.h"

namespace clothfit {

// The nine counts of a texel (level 0) or of a block of texels (a mip
// level), in this order (also the order of the EXR channels).
enum HoleCountIndex : int {
  kWallTop = 0,     // transparent texel whose +y neighbour is opaque
  kWallLeft = 1,    // ... -x neighbour
  kWallBottom = 2,  // ... -y neighbour
  kWallRight = 3,   // ... +x neighbour
  // Transparent texel whose diagonal neighbour is opaque: the number (0..2)
  // of the two texels between them that are not opaque.
  kTriangleTopRight = 4,     // diagonal (+x, +y)
  kTriangleTopLeft = 5,      // diagonal (-x, +y)
  kTriangleBottomLeft = 6,   // diagonal (-x, -y)
  kTriangleBottomRight = 7,  // diagonal (+x, -y)
  kOpaques = 8,              // opaque texel
};
inline constexpr int kHoleCountChannels = 9;

// Channel names of the count images, in HoleCountIndex order.
inline const char* const* HoleCountNames() {
  static const char* const kNames[kHoleCountChannels] = {
      "walls.top",
      "walls.left",
      "walls.bottom",
      "walls.right",
      "triangles.topRight",
      "triangles.topLeft",
      "triangles.bottomLeft",
      "triangles.bottomRight",
      "opaques"};
  return kNames;
}

// One texel of a count image: the nine counts and the number T of base
// texels they sum (4^l at level l of a power-of-two mask; the block's area
// otherwise).
struct HoleTexel {
  std::array<double, kHoleCountChannels> counts{};
  double texels = 1.0;
};

// Fractions of the rays landing on the texel (they sum to 1).
template <typename T>
struct HoleRatiosT {
  T opaque = T(0.0);       // hit the top of a column
  T occluded = T(0.0);     // entered a hole and met a wall
  T transparent = T(0.0);  // passed through
};
using HoleRatios = HoleRatiosT<double>;

// Smallest |wo.z| used by ViewOffset (a grazing view travels ~1e9 h).
inline constexpr double kMinCosView = 1e-9;

// r = -h wo.xy / |wo.z|: how far (in texels) the view ray travels sideways
// while it crosses the thickness h (docs/models.md). The same for a viewer on
// either side (wo.z < 0: the ray crosses the layer upwards).
template <typename T>
Vec2<T> ViewOffset(const T& h, const glm::dvec3& wo) {
  const double z = Max(std::abs(wo.z), kMinCosView);
  return Vec2<T>(h * T(-wo.x / z), h * T(-wo.y / z));
}

// The occluded count O of Algorithm 3.1 (the rays that meet a wall, in
// units of texel areas) for the offset r, with |rx|, |ry| clamped to 1.
template <typename T>
T OccludedCount31(const HoleTexel& t, const Vec2<T>& r) {
  const T rx = Clamp(r.x, T(-1.0), T(1.0));
  const T ry = Clamp(r.y, T(-1.0), T(1.0));
  const double* c = t.counts.data();
  const bool right = rx > T(0.0), left = rx < T(0.0);
  const bool top = ry > T(0.0), bottom = ry < T(0.0);
  const double h_walls = right ? c[kWallRight] : left ? c[kWallLeft] : 0.0;
  const double v_walls = top ? c[kWallTop] : bottom ? c[kWallBottom] : 0.0;
  double d = 0.0;
  if (right && top) d = c[kTriangleTopRight];
  if (right && bottom) d = c[kTriangleBottomRight];
  if (left && top) d = c[kTriangleTopLeft];
  if (left && bottom) d = c[kTriangleBottomLeft];
  const T ax = right ? rx : -rx;
  const T ay = top ? ry : -ry;
  const T half = T(0.5) * ax * ay;
  return T(h_walls) * (ax - half) + T(v_walls) * (ay - half) + T(d) * half;
}

// Algorithm 3.1: rho_occluded = O / T, rho_opaque = opaques / T,
// rho_transparent = 1 - rho_occluded - rho_opaque.
template <typename T>
HoleRatiosT<T> Algorithm31(const HoleTexel& t, const Vec2<T>& r) {
  HoleRatiosT<T> out;
  const double inv_texels = 1.0 / t.texels;
  out.opaque = T(t.counts[kOpaques] * inv_texels);
  out.occluded = OccludedCount31(t, r) * T(inv_texels);
  out.transparent = T(1.0) - out.occluded - out.opaque;
  return out;
}

// The parameter table of a holed layer seen in transmission
// (models/params.h). A fit searches the thickness in [1e-3, 1e3].
inline constexpr ParamInfo kHolesThickness = {
    "thickness_texels",
    "texel widths",
    "height h of the opaque columns",
    {0.0, 1e4, true, false},
    1e-3,
    1e3,
    false,
    {1.0},
    "David-Babin 2022, §3.3 and Algorithm 3.1 (h; Fig. 4.4 uses 0.1-1)",
    1};
// Eq. 3.4.3's c_2 for a white background (c_alpha = 1) behind tops that
// pass no light (c_1 = 0); 0: walls block light.
inline constexpr ParamInfo kHolesWallColor = {
    "wall_color",
    "unitless",
    "fraction of the light meeting a hole's wall that reaches the sensor",
    {0.0, 1.0},
    0.0,
    1.0,
    true,
    {0.0, 0.0, 0.0},
    "David-Babin 2022, eq. 3.4.3 (c_2)",
    3};

template <typename T>
struct HolesParamsT {
  T thickness_texels = kHolesThickness.Default<T>();
  Vec3<T> wall_color = kHolesWallColor.DefaultRgb<T>();
};
using HolesParams = HolesParamsT<double>;

template <typename T, typename F>
void VisitParams(HolesParamsT<T>& p, F&& f) {
  f(kHolesThickness, p.thickness_texels);
  f(kHolesWallColor, p.wall_color);
}

// Transmittance per channel (Eq. 3.4.3 with c_1 = 0, c_alpha = 1) of a
// texel or tile with the given ratios: rho_transparent + wall_color
// rho_occluded.
template <typename T>
Vec3<T> TransmittanceOfRatios(const HolesParamsT<T>& p,
                              const HoleRatiosT<T>& ratios) {
  return Vec3<T>(ratios.transparent) + p.wall_color * ratios.occluded;
}

}  // namespace clothfit
