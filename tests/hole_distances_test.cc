// The extension's run counts against their definition (models/
// holes_distance.h): per texel by stepping through the tiling mask, summed
// over each block of every level, in the pyramid and in the EXR that
// WriteCountPyramid writes (value by value, as floats).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <string>
#include <vector>

#include "data_synthetic/holes_truth.h"
#include "holes/hole_texture.h"
#include "io/hole_exr.h"
#include "io/param_mipmap.h"
#include "tests/io_test_util.h"

namespace clothfit {
namespace {

namespace fs = std::filesystem;

// C_d[j] of texel (x, y) from the definition: k_d transparent texels before
// the first opaque one along d (kDistanceBins: none within reach); a
// diagonal only where it is shorter than both axial runs of its quadrant.
std::array<int, kDistanceChannels> CumulativeByDefinition(const Mask& m, int x,
                                                          int y) {
  std::array<int, kDistanceChannels> c{};
  if (m.Opaque(x, y)) return c;
  int runs[kDirections8];
  for (int d = 0; d < kDirections8; ++d) {
    int dx, dy;
    Direction8Step(d, &dx, &dy);
    int k = 0;
    while (k < kDistanceBins && !m.Opaque(x + (k + 1) * dx, y + (k + 1) * dy)) {
      ++k;
    }
    runs[d] = k;
  }
  const int quadrant[4][3] = {{kNorthEast, kEast, kNorth},
                              {kNorthWest, kWest, kNorth},
                              {kSouthWest, kWest, kSouth},
                              {kSouthEast, kEast, kSouth}};
  for (const auto& q : quadrant) {
    if (runs[q[0]] >= std::min(runs[q[1]], runs[q[2]])) {
      runs[q[0]] = kDistanceBins;
    }
  }
  for (int d = 0; d < kDirections8; ++d) {
    for (int j = 0; j < kDistanceBins; ++j) {
      c[d * kDistanceBins + j] = runs[d] <= j;
    }
  }
  return c;
}

// The definition summed over the block of texel (x, y) of `level`.
std::array<double, kDistanceChannels> BlockByDefinition(const Mask& mask,
                                                        const CountPyramid& p,
                                                        int level, int x,
                                                        int y) {
  int x0, y0, x1, y1;
  p.Block(level, x, y, &x0, &y0, &x1, &y1);
  std::array<double, kDistanceChannels> sum{};
  for (int by = y0; by < y1; ++by) {
    for (int bx = x0; bx < x1; ++bx) {
      const auto c = CumulativeByDefinition(mask, bx, by);
      for (int k = 0; k < kDistanceChannels; ++k) sum[k] += c[k];
    }
  }
  return sum;
}

// Half the texels opaque and a 70 x 45 mask: the last blocks of levels 4
// and 5 (22 x 29 and 38 x 45 texels) count more than 255, so the pyramid's
// 16-bit levels are checked too.
TEST(HoleDistancesTest, PyramidAndFileHoldTheRunsByDefinition) {
  const Mask mask = RandomMask(70, 45, 0.5, 11);
  const CountPyramid p = HoleDistancesFromMask(mask);
  const fs::path dir = testing_util::FreshTestDir("hole_distances_test_");
  const std::string path = (dir / "d.exr").string();
  WriteCountPyramid(p, CountKind::kHoleDistances, "", path);
  const ParamMipmap file = ReadParamMipmap(path);
  ASSERT_EQ(static_cast<int>(file.levels.size()), p.levels());
  double largest = 0.0;
  for (int level = 0; level < p.levels(); ++level) {
    const ParamImage& image = file.levels[level];
    ASSERT_EQ(image.width, p.width(level));
    ASSERT_EQ(image.height, p.height(level));
    for (int y = 0; y < p.height(level); ++y) {
      for (int x = 0; x < p.width(level); ++x) {
        const auto expected = BlockByDefinition(mask, p, level, x, y);
        const HoleDistanceTexel got = DistanceTexelAt(p, level, x, y);
        for (int k = 0; k < kDistanceChannels; ++k) {
          ASSERT_EQ(got.cumulative[k], expected[k])
              << "level " << level << " texel " << x << "," << y << " " << k;
          ASSERT_EQ(image.data[k][static_cast<size_t>(y) * image.width + x],
                    static_cast<float>(expected[k]))
              << "file level " << level << " texel " << x << "," << y;
          largest = std::max(largest, expected[k]);
        }
      }
    }
  }
  EXPECT_GT(largest, 255.0);
}

}  // namespace
}  // namespace clothfit
