#include "holes/hole_texture.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <opencv2/core.hpp>
#include <stdexcept>
#include <utility>
#include <vector>

#include "io/input_error.h"

namespace clothfit {
namespace {

// Index tables that wrap [-margin, size + margin) onto [0, size).
std::vector<int> WrapTable(int size, int margin) {
  std::vector<int> table(size + 2 * margin);
  for (int i = 0; i < static_cast<int>(table.size()); ++i) {
    table[i] = ((i - margin) % size + size) % size;
  }
  return table;
}

void RequireDistances(const HoleTexture& texture, HoleMethod method) {
  if (method == HoleMethod::kExtension && texture.distances.empty()) {
    throw std::invalid_argument(
        "the extension needs the run counts (AnalyzeMask with distances)");
  }
}

// Adds the ratios of `b` times w to *a.
void Accumulate(const HoleRatios& b, double w, HoleRatios* a) {
  a->opaque += w * b.opaque;
  a->occluded += w * b.occluded;
  a->transparent += w * b.transparent;
}

// Bilinear interpolation of the method's ratios on one level.
HoleRatios SampleLevel(const HoleTexture& texture, HoleMethod method, int level,
                       const glm::dvec2& position, const glm::dvec2& r) {
  const CountPyramid& counts = texture.counts;
  const int w = counts.width(level), h = counts.height(level);
  // Level coordinates: the base size W maps onto the level's w texels.
  const double fx = position.x * w / counts.width(0) - 0.5;
  const double fy = position.y * h / counts.height(0) - 0.5;
  const double x0 = std::floor(fx), y0 = std::floor(fy);
  const double ax = fx - x0, ay = fy - y0;
  auto wrap = [](double i, int n) {
    const int64_t k = static_cast<int64_t>(i) % n;
    return static_cast<int>(k < 0 ? k + n : k);
  };
  HoleRatios out;
  for (int j = 0; j < 2; ++j) {
    for (int i = 0; i < 2; ++i) {
      const double weight = (i ? ax : 1.0 - ax) * (j ? ay : 1.0 - ay);
      if (weight == 0.0) continue;
      Accumulate(EvaluateTexel(texture, method, level, wrap(x0 + i, w),
                               wrap(y0 + j, h), r),
                 weight, &out);
    }
  }
  return out;
}

}  // namespace

CountPyramid HoleCountsFromMask(const Mask& mask) {
  const int w = mask.width, h = mask.height;
  // The mask with a one-texel border that wraps (the tiling), so that every
  // texel's eight neighbours are plain reads.
  const cv::Mat opaque(h, w, CV_8U, const_cast<uint8_t*>(mask.opaque.data()));
  cv::Mat padded;
  cv::copyMakeBorder(opaque, padded, 1, 1, 1, 1, cv::BORDER_WRAP);
  std::vector<uint8_t> base(static_cast<size_t>(w) * h * kHoleCountChannels);
  // One pass over the texels (OpenCV's per-plane operations and the merge
  // into interleaved channels took three times as long on 4096 x 4096).
  for (int y = 0; y < h; ++y) {
    const uint8_t* down = padded.ptr<uint8_t>(y) + 1;  // row y - 1 (-y)
    const uint8_t* mid = padded.ptr<uint8_t>(y + 1) + 1;
    const uint8_t* up = padded.ptr<uint8_t>(y + 2) + 1;  // row y + 1 (+y)
    uint8_t* out =
        base.data() + static_cast<size_t>(y) * w * kHoleCountChannels;
    for (int x = 0; x < w; ++x, out += kHoleCountChannels) {
      const int o = mid[x], t = 1 - o;
      const int left = mid[x - 1], right = mid[x + 1];
      const int top = up[x], bottom = down[x];
      out[kWallTop] = static_cast<uint8_t>(t & top);
      out[kWallLeft] = static_cast<uint8_t>(t & left);
      out[kWallBottom] = static_cast<uint8_t>(t & bottom);
      out[kWallRight] = static_cast<uint8_t>(t & right);
      // Diagonal opaque: the number of the two texels between that are not.
      out[kTriangleTopRight] =
          static_cast<uint8_t>((t & up[x + 1]) * (2 - right - top));
      out[kTriangleTopLeft] =
          static_cast<uint8_t>((t & up[x - 1]) * (2 - left - top));
      out[kTriangleBottomLeft] =
          static_cast<uint8_t>((t & down[x - 1]) * (2 - left - bottom));
      out[kTriangleBottomRight] =
          static_cast<uint8_t>((t & down[x + 1]) * (2 - right - bottom));
      out[kOpaques] = static_cast<uint8_t>(o);
    }
  }
  return CountPyramid(w, h, kHoleCountChannels, std::move(base));
}

CountPyramid HoleDistancesFromMask(const Mask& mask) {
  const int w = mask.width, h = mask.height;
  const int margin = kDistanceBins + 1;
  const std::vector<int> cols = WrapTable(w, margin);
  const std::vector<int> rows = WrapTable(h, margin);
  // One bit per indicator (0.13 GB for a 4096 x 4096 mask, not 1.1 GB).
  static_assert(kDistanceChannels <= 64, "the run counts fill one word");
  std::vector<uint64_t> bits(static_cast<size_t>(w) * h, 0);
  int runs[kDirections8];
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      if (mask.opaque[static_cast<size_t>(y) * w + x]) continue;
      for (int d = 0; d < kDirections8; ++d) {
        int dx, dy;
        Direction8Step(d, &dx, &dy);
        int k = 0;  // transparent texels before the first opaque one
        while (k < kDistanceBins) {
          const int sx = cols[x + (k + 1) * dx + margin];
          const int sy = rows[y + (k + 1) * dy + margin];
          if (mask.opaque[static_cast<size_t>(sy) * w + sx]) break;
          ++k;
        }
        runs[d] = k;  // kDistanceBins: none within reach
      }
      // A diagonal counts only where it is shorter than both axial runs of
      // its quadrant (models/holes_distance.h).
      const int axes[4][2] = {
          {kEast, kNorth}, {kWest, kNorth}, {kWest, kSouth}, {kEast, kSouth}};
      for (int q = 0; q < 4; ++q) {
        int& diagonal = runs[kNorthEast + q];
        if (diagonal >= std::min(runs[axes[q][0]], runs[axes[q][1]])) {
          diagonal = kDistanceBins;
        }
      }
      // C_d[j] = [k_d <= j]: bits runs[d] .. kDistanceBins - 1 of
      // direction d's bins.
      uint64_t word = 0;
      for (int d = 0; d < kDirections8; ++d) {
        const uint64_t bins = (uint64_t{1} << kDistanceBins) - 1;
        const uint64_t below = (uint64_t{1} << runs[d]) - 1;
        word |= (bins & ~below) << (d * kDistanceBins);
      }
      bits[static_cast<size_t>(y) * w + x] = word;
    }
  }
  return CountPyramid(w, h, kDistanceChannels, std::move(bits));
}

HoleTexture AnalyzeMask(const Mask& mask, bool with_distances) {
  HoleTexture texture;
  texture.counts = HoleCountsFromMask(mask);
  if (with_distances) texture.distances = HoleDistancesFromMask(mask);
  return texture;
}

HoleTexel HoleTexelAt(const CountPyramid& counts, int level, int x, int y) {
  HoleTexel t;
  counts.Counts(level, x, y, t.counts.data());
  t.texels = counts.Texels(level, x, y);
  return t;
}

HoleDistanceTexel DistanceTexelAt(const CountPyramid& distances, int level,
                                  int x, int y) {
  HoleDistanceTexel d;
  distances.Counts(level, x, y, d.cumulative.data());
  return d;
}

HoleRatios EvaluateTexel(const HoleTexture& texture, HoleMethod method,
                         int level, int x, int y, const glm::dvec2& r) {
  const HoleTexel t = HoleTexelAt(texture.counts, level, x, y);
  if (method == HoleMethod::kAlgorithm31) return Algorithm31(t, r);
  RequireDistances(texture, method);
  return ExtendedRatios(t, DistanceTexelAt(texture.distances, level, x, y), r);
}

LevelTexels GatherLevel(const HoleTexture& texture, int level) {
  const CountPyramid& counts = texture.counts;
  LevelTexels out;
  for (int y = 0; y < counts.height(level); ++y) {
    for (int x = 0; x < counts.width(level); ++x) {
      out.counts.push_back(HoleTexelAt(counts, level, x, y));
      if (!texture.distances.empty()) {
        out.distances.push_back(
            DistanceTexelAt(texture.distances, level, x, y));
      }
    }
  }
  out.area = static_cast<double>(counts.width(0)) *
             static_cast<double>(counts.height(0));
  return out;
}

HolesTile HolesTileOf(const HoleTexture& texture, HoleMethod method,
                      int level) {
  const int top = texture.counts.levels() - 1;
  if (level < 0) level = top;
  if (level > top) {
    throw InputError("level " + std::to_string(level) +
                     " is out of range: the mask's pyramid has levels 0.." +
                     std::to_string(top));
  }
  if (method == HoleMethod::kExtension && texture.distances.empty()) {
    throw InputError("the extension needs the mask's run counts");
  }
  HolesTile tile;
  tile.method = method;
  tile.texels = GatherLevel(texture, level);
  return tile;
}

HolesModel LoadHolesModel(const ParamFile& file, const std::string& path,
                          const std::string& mask) {
  HolesModel model = ModelOf<HolesModel>(file, path);
  if (mask.empty() && model.tile) return model;  // the file's own tile
  std::string mask_path = mask;
  if (mask_path.empty() && !file.holes.path.empty()) {
    mask_path =
        (std::filesystem::path(path).parent_path() / file.holes.path).string();
  }
  if (mask_path.empty()) {
    throw InputError(path +
                     ": a holes model needs its mask: the file names "
                     "none (give --mask M.png)");
  }
  MaskReadOptions mask_options;
  mask_options.threshold = file.holes.threshold;
  const HoleMethod method = file.holes.method.value_or(HoleMethod::kExtension);
  const HoleTexture texture = AnalyzeMask(ReadMask(mask_path, mask_options),
                                          method == HoleMethod::kExtension);
  model.tile = std::make_shared<const HolesTile>(HolesTileOf(texture, method));
  return model;
}

HoleRatios EvaluateTile(const HoleTexture& texture, HoleMethod method,
                        int level, const glm::dvec2& r) {
  RequireDistances(texture, method);
  return TileRatios(GatherLevel(texture, level), method, r);
}

HoleRatios SampleTrilinear(const HoleTexture& texture, HoleMethod method,
                           const glm::dvec2& position, double lod,
                           const glm::dvec2& r) {
  const int top = texture.counts.levels() - 1;
  const double l = std::clamp(lod, 0.0, static_cast<double>(top));
  const int l0 = static_cast<int>(std::floor(l));
  const int l1 = std::min(l0 + 1, top);
  const double f = l - l0;
  HoleRatios out;
  Accumulate(SampleLevel(texture, method, l0, position, r), 1.0 - f, &out);
  if (f > 0.0) {
    Accumulate(SampleLevel(texture, method, l1, position, r), f, &out);
  }
  return out;
}

}  // namespace clothfit
