// A mask analysed for Algorithm 3.1 (David-Babin 2022) and its extension:
// the nine count images (models/holes.h) and the cumulative run counts
// (models/holes_distance.h), each as a summed mip pyramid down to 1 x 1
// (io/count_pyramid.h), and their evaluation at any level, for the
// whole tile, or trilinearly filtered between levels.
#pragma once

#include <glm/vec2.hpp>
#include <optional>
#include <string>
#include <vector>

#include "io/count_pyramid.h"
#include "io/mask_io.h"
#include "io/params_json.h"
#include "models/holes_tile.h"

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

// The model of a holes parameter file read from `path` (io/params_json.h):
// the file's tile when it has one and `mask` is empty; else its mask -
// `mask` when not empty, else the file's "mask" relative to the file's
// folder - read with the file's threshold and analysed, evaluated at the
// top level with the file's method (the extension by default).
// Throws InputError naming the file when there is no mask to read.
HolesModel LoadHolesModel(const ParamFile& file, const std::string& path,
                          const std::string& mask = "");

// The ratios of texel (x, y) of `level` for the view offset r (texels,
// models/holes.h ViewOffset). The extension needs texture.distances
// (throws std::invalid_argument otherwise).
HoleRatios EvaluateTexel(const HoleTexture& texture, HoleMethod method,
                         int level, int x, int y, const glm::dvec2& r);

// The texels of one level (models/holes_tile.h; distances when the
// texture has them).
LevelTexels GatherLevel(const HoleTexture& texture, int level);

// The tile a fit or an evaluation averages over: level `level` (kTopLevel:
// the 1 x 1 level) with `method`. Algorithm 3.1 gives the same at every
// level; the extension is exact on rectangular holes at every level, and
// on irregular masks its error depends on the level (docs/holes.md);
// lower levels cost more per evaluation. Throws InputError for a level out
// of range and for the extension without the texture's distances.
inline constexpr int kTopLevel = -1;
HolesTile HolesTileOf(const HoleTexture& texture,
                      HoleMethod method = HoleMethod::kExtension,
                      int level = kTopLevel);

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
