// A mask analysed for Algorithm 3.1 (David-Babin 2022) and its extension:
// the nine count images (models/holes.h) and the cumulative run counts
// (models/holes_distance.h), each as a summed mip pyramid down to 1 x 1
// (holes/count_pyramid.h), and their evaluation at any level, for the
// whole tile, or trilinearly filtered between levels.
#pragma once

#include <glm/vec2.hpp>
#include <optional>
#include <string>
#include <vector>

#include "holes/count_pyramid.h"
#include "io/mask_io.h"
#include "models/holes.h"
#include "models/holes_distance.h"

namespace clothfit {

// The nine counts per texel (walls, triangles, opaque; models/holes.h) of a
// tiling mask, computed with OpenCV (neighbours through a BORDER_WRAP
// border), and their pyramid.
CountPyramid HoleCountsFromMask(const Mask& mask);

// The cumulative run counts C_d[j] per texel (kDistanceChannels channels,
// models/holes_distance.h) of a tiling mask, and their pyramid.
CountPyramid HoleDistancesFromMask(const Mask& mask);

struct HoleTexture {
  CountPyramid counts;     // kHoleCountChannels channels
  CountPyramid distances;  // kDistanceChannels channels, or empty
};

// Both pyramids (distances only when asked: they take 64 counts per texel).
HoleTexture AnalyzeMask(const Mask& mask, bool with_distances);

HoleTexel HoleTexelAt(const CountPyramid& counts, int level, int x, int y);
HoleDistanceTexel DistanceTexelAt(const CountPyramid& distances, int level,
                                  int x, int y);

enum class HoleMethod {
  kAlgorithm31,  // the thesis, |rx|, |ry| clamped to 1
  kExtension,    // + the run counts beyond one texel (needs distances)
};
const char* HoleMethodName(HoleMethod method);  // "alg31" | "extension"
std::optional<HoleMethod> ParseHoleMethod(const std::string& text);

// The ratios of texel (x, y) of `level` for the view offset r (texels,
// models/holes.h ViewOffset). The extension needs texture.distances
// (throws std::invalid_argument otherwise).
HoleRatios EvaluateTexel(const HoleTexture& texture, HoleMethod method,
                         int level, int x, int y, const glm::dvec2& r);

// The texels of one level, gathered for repeated whole-tile evaluation
// (distances empty unless the texture has them).
struct LevelTexels {
  std::vector<HoleTexel> counts;
  std::vector<HoleDistanceTexel> distances;
  double area = 0.0;  // base texels of the tile
};
LevelTexels GatherLevel(const HoleTexture& texture, int level);

// The whole tile: the area-weighted mean of the level's texels, sum_i T_i
// ratios_i / area. Algorithm 3.1 gives the same at every level (it is
// linear in the counts); the extension is exact on rectangular holes at
// every level and depends on the level elsewhere (docs/holes.md).
// Templated for the fit (fitting/holes_fit.h).
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

// TileRatios of one level of the texture (GatherLevel, then TileRatios);
// the extension needs the distances (std::invalid_argument otherwise).
HoleRatios EvaluateTile(const HoleTexture& texture, HoleMethod method,
                        int level, const glm::dvec2& r);

// Trilinear filtering (David-Babin 2022 §2.4 and §3.4): the method is
// evaluated at the 4 texels around `position` (in base texels; the texture
// wraps) on levels floor(lod) and floor(lod) + 1, and the ratios are
// interpolated bilinearly on each level, then linearly between the levels
// (lod is clamped to [0, levels - 1]). Texel centres of level l sit at
// (x + 0.5) W / width(l) in base texels.
HoleRatios SampleTrilinear(const HoleTexture& texture, HoleMethod method,
                           const glm::dvec2& position, double lod,
                           const glm::dvec2& r);

}  // namespace clothfit
