// The transmittance of a whole tile of a holed layer (David-Babin 2022;
// SPEC §3.5): the texels of one mip level of a mask's count pyramid
// (models/holes.h, models/holes_distance.h), the method that turns their
// counts into ratios, and the one function that evaluates the model,
// HolesTransmittance. The counts come from a mask (holes/hole_texture.h);
// here they are plain data.
#pragma once

#include <memory>
#include <vector>

#include "models/holes.h"
#include "models/holes_distance.h"
#include "models/params.h"

namespace clothfit {

enum class HoleMethod {
  kAlgorithm31,  // the thesis, |rx|, |ry| clamped to 1
  kExtension,    // + the run counts beyond one texel (needs distances)
};

// "alg31" | "extension".
inline const char* HoleMethodName(HoleMethod method) {
  return method == HoleMethod::kAlgorithm31 ? "alg31" : "extension";
}

// The texels of one level, gathered for repeated whole-tile evaluation
// (distances empty unless the texture has them).
struct LevelTexels {
  std::vector<HoleTexel> counts;
  std::vector<HoleDistanceTexel> distances;
  double area = 0.0;  // base texels of the tile
};

// The whole tile: the area-weighted mean of the level's texels, sum_i T_i
// ratios_i / area. Algorithm 3.1 gives the same at every level (it is
// linear in the counts); the extension is exact on rectangular holes at
// every level and depends on the level elsewhere (docs/holes.md). The
// extension without distances is Algorithm 3.1.
template <typename T>
HoleRatiosT<T> TileRatios(const LevelTexels& level, HoleMethod method,
                          const Vec2<T>& r) {
  HoleRatiosT<T> sum;
  const bool extension =
      method == HoleMethod::kExtension && !level.distances.empty();
  for (size_t i = 0; i < level.counts.size(); ++i) {
    const HoleTexel& t = level.counts[i];
    const HoleRatiosT<T> ratios = extension
                                      ? ExtendedRatios(t, level.distances[i], r)
                                      : Algorithm31(t, r);
    sum.opaque += T(t.texels) * ratios.opaque;
    sum.occluded += T(t.texels) * ratios.occluded;
    sum.transparent += T(t.texels) * ratios.transparent;
  }
  const T inv_area = T(1.0 / level.area);
  sum.opaque *= inv_area;
  sum.occluded *= inv_area;
  sum.transparent *= inv_area;
  return sum;
}

// A tile's texels and the method they are evaluated with.
struct HolesTile {
  HoleMethod method = HoleMethod::kExtension;
  LevelTexels texels;
};

// The ratios of the tile for the view wo with parameters p: those of the
// view offset of thickness h (Algorithm 3.1 or the extension).
template <typename T>
HoleRatiosT<T> HolesTileRatios(const HolesParamsT<T>& p, const HolesTile& tile,
                               const glm::dvec3& wo) {
  return TileRatios(tile.texels, tile.method,
                    ViewOffset(p.thickness_texels, wo));
}

// The model: the transmittance of the tile for the view wo,
// rho_transparent + wall_color rho_occluded (Eq. 3.4.3).
template <typename T>
Vec3<T> HolesTransmittance(const HolesParamsT<T>& p, const HolesTile& tile,
                           const glm::dvec3& wo) {
  return TransmittanceOfRatios(p, HolesTileRatios(p, tile, wo));
}

// A holed layer: its parameters and its mask's tile (shared: a tile of a
// large mask is large). A parameter file names the mask; `tile` is null
// until the mask is analysed (holes/hole_texture.h HolesModelOfMask).
struct HolesModel {
  HolesParams params;
  std::shared_ptr<const HolesTile> tile;
};

template <>
inline constexpr ModelInfo kModelInfo<HolesModel> = {
    "holes", Quantity::kTransmittance, true};

// Requires the tile (ValidateModel in models/evaluate.h says so); 0
// without one.
inline glm::dvec3 Transmittance(const HolesModel& m, const glm::dvec3& wo) {
  if (!m.tile) return glm::dvec3(0.0);
  return HolesTransmittance(m.params, *m.tile, wo);
}

inline glm::dvec3 NativeValue(const HolesModel& m, const glm::dvec3&,
                              const glm::dvec3& wo) {
  return Transmittance(m, wo);
}

}  // namespace clothfit
