// The transmittance of a whole tile of a holed layer (David-Babin 2022;
// docs/models.md): the texels of one mip level of a mask's count pyramid
// (models/holes.h, models/holes_distance.h), the method that turns their
// counts into ratios, and the one function that evaluates the model,
// HolesTransmittance. The counts come from a mask (holes/hole_texture.h);
// here they are plain data.
#pragma once

#include <cmath>
#include <memory>
#include <string>
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

// Most texels a tile stored in a parameter file may have (io/params_json.h
// "tile"): 4,096 texels of 73 numbers (a 64 x 64 level) are ~2 MB of JSON.
inline constexpr size_t kMaxStoredTileTexels = 4096;

// "" when `tile` is one a mask can give, else what is wrong: at least one
// texel; distances for every texel when the method is the extension (and
// none or one per texel otherwise); every texel's base-texel count T
// positive and finite and their sum the area; each count in [0, 2 T] (a
// triangle counts up to 2 per base texel), each cumulative run count in
// [0, T] and non-decreasing with the distance.
inline std::string ValidateHolesTile(const HolesTile& tile) {
  const LevelTexels& l = tile.texels;
  if (l.counts.empty()) return "tile: has no texels";
  if (tile.method == HoleMethod::kExtension && l.distances.empty()) {
    return "tile: the extension needs the run counts (distances)";
  }
  if (!l.distances.empty() && l.distances.size() != l.counts.size()) {
    return "tile: " + std::to_string(l.distances.size()) +
           " texels of distances for " + std::to_string(l.counts.size()) +
           " texels of counts";
  }
  double sum = 0.0;
  for (size_t i = 0; i < l.counts.size(); ++i) {
    const std::string at = "tile.texels[" + std::to_string(i) + "]";
    const double t = l.counts[i].texels;
    if (!(t > 0.0 && t < 1e300)) return at + ": must be positive and finite";
    sum += t;
    for (double c : l.counts[i].counts) {
      if (!(c >= 0.0 && c <= 2.0 * t)) {
        return "tile.counts[" + std::to_string(i) +
               "]: each count must be in [0, " + std::to_string(2.0 * t) + "]";
      }
    }
    if (l.distances.empty()) continue;
    const auto& d = l.distances[i].cumulative;
    for (int dir = 0; dir < kDirections8; ++dir) {
      for (int j = 0; j < kDistanceBins; ++j) {
        const double c = d[dir * kDistanceBins + j];
        const double before = j > 0 ? d[dir * kDistanceBins + j - 1] : 0.0;
        if (!(c >= before && c <= t)) {
          return "tile.distances[" + std::to_string(i) +
                 "]: run counts must be non-decreasing in [0, " +
                 std::to_string(t) + "] per direction";
        }
      }
    }
  }
  if (!(l.area > 0.0) || !(std::abs(sum - l.area) <= 1e-9 * l.area)) {
    return "tile.area: must be the sum of the texels' counts (" +
           std::to_string(sum) + ")";
  }
  return "";
}

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
