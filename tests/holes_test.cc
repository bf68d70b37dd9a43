// Semi-transparent textures with thickness: the counts, their
// pyramid, Algorithm 3.1 and the extension against the ground truth, and
// the ground truth itself against closed forms.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "data_synthetic/holes_truth.h"
#include "data_synthetic/synthetic_table.h"
#include "holes/hole_texture.h"

namespace clothfit {
namespace {

// Samples per texel side of the ground truth, and the bound 2 / n on its
// integration error per texel for |rx|, |ry| <= 1 (holes_truth.h).
constexpr int kSamples = 128;
constexpr double kTruthError = 2.0 / kSamples;

// The nine counts of texel (x, y) straight from docs/models.md's definitions.
std::array<int, kHoleCountChannels> CountsByDefinition(const Mask& m, int x,
                                                       int y) {
  std::array<int, kHoleCountChannels> c{};
  if (m.Opaque(x, y)) {
    c[kOpaques] = 1;
    return c;
  }
  c[kWallTop] = m.Opaque(x, y + 1);
  c[kWallLeft] = m.Opaque(x - 1, y);
  c[kWallBottom] = m.Opaque(x, y - 1);
  c[kWallRight] = m.Opaque(x + 1, y);
  const int quadrant[4][3] = {{kTriangleTopRight, 1, 1},
                              {kTriangleTopLeft, -1, 1},
                              {kTriangleBottomLeft, -1, -1},
                              {kTriangleBottomRight, 1, -1}};
  for (const auto& q : quadrant) {
    if (m.Opaque(x + q[1], y + q[2])) {
      c[q[0]] = !m.Opaque(x + q[1], y) + !m.Opaque(x, y + q[2]);
    }
  }
  return c;
}

// The ground truth of every base texel for offset r (row-major).
std::vector<HoleRatios> TexelTruths(const Mask& mask, const glm::dvec2& r) {
  std::vector<HoleRatios> out;
  for (int y = 0; y < mask.height; ++y) {
    for (int x = 0; x < mask.width; ++x) {
      out.push_back(
          HoleTruth(mask, r, BlockFootprint(x, y, x + 1, y + 1, kSamples)));
    }
  }
  return out;
}

// The mean of the texel truths over a block (= the truth sampled over it).
HoleRatios BlockTruth(const std::vector<HoleRatios>& truths, const Mask& mask,
                      int x0, int y0, int x1, int y1) {
  HoleRatios sum;
  for (int y = y0; y < y1; ++y) {
    for (int x = x0; x < x1; ++x) {
      const HoleRatios& t = truths[static_cast<size_t>(y) * mask.width + x];
      sum.opaque += t.opaque;
      sum.occluded += t.occluded;
      sum.transparent += t.transparent;
    }
  }
  const double n = static_cast<double>(x1 - x0) * (y1 - y0);
  return HoleRatios{sum.opaque / n, sum.occluded / n, sum.transparent / n};
}

glm::dvec3 View(double theta_deg, double phi_deg) {
  const double t = Radians(theta_deg), p = Radians(phi_deg);
  return glm::dvec3(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p),
                    std::cos(t));
}

TEST(HoleCountsTest, SingleOpaqueTexel) {
  const Mask mask = MaskFromRows({"....", ".#..", "....", "...."});
  const CountPyramid counts = HoleCountsFromMask(mask);
  auto at = [&](int x, int y, int c) {
    return HoleTexelAt(counts, 0, x, y).counts[c];
  };
  EXPECT_EQ(at(1, 1, kOpaques), 1);
  EXPECT_EQ(at(0, 1, kWallRight), 1);  // left of the column: wall at +x
  EXPECT_EQ(at(2, 1, kWallLeft), 1);
  EXPECT_EQ(at(1, 0, kWallTop), 1);  // row 0: the column is at +y
  EXPECT_EQ(at(1, 2, kWallBottom), 1);
  EXPECT_EQ(at(0, 0, kTriangleTopRight), 2);
  EXPECT_EQ(at(2, 0, kTriangleTopLeft), 2);
  EXPECT_EQ(at(2, 2, kTriangleBottomLeft), 2);
  EXPECT_EQ(at(0, 2, kTriangleBottomRight), 2);
  double total = 0.0;
  for (int y = 0; y < 4; ++y) {
    for (int x = 0; x < 4; ++x) {
      for (double c : HoleTexelAt(counts, 0, x, y).counts) total += c;
    }
  }
  EXPECT_EQ(total, 1 + 4 + 4 * 2);  // nothing else
}

TEST(HoleCountsTest, MatchDefinitionsWithTilingOnRandomMasks) {
  for (const auto& [w, h] :
       std::vector<std::pair<int, int>>{{16, 16}, {7, 5}, {1, 9}, {2, 1}}) {
    const Mask mask = RandomMask(w, h, 0.4, 100 + w * h);
    const CountPyramid counts = HoleCountsFromMask(mask);
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const auto expected = CountsByDefinition(mask, x, y);
        const HoleTexel t = HoleTexelAt(counts, 0, x, y);
        for (int c = 0; c < kHoleCountChannels; ++c) {
          EXPECT_EQ(t.counts[c], expected[c])
              << w << "x" << h << " texel " << x << "," << y << " channel "
              << HoleCountNames()[c];
        }
      }
    }
  }
}

TEST(HolePyramidTest, LevelsSumLevelZeroOverTheirBlocks) {
  for (const auto& [w, h] : std::vector<std::pair<int, int>>{
           {16, 16}, {12, 10}, {7, 5}, {1, 9}, {6, 6}}) {
    const Mask mask = RandomMask(w, h, 0.5, 7 + w);
    const CountPyramid counts = HoleCountsFromMask(mask);
    ASSERT_EQ(counts.levels(),
              1 + static_cast<int>(std::floor(std::log2(std::max(w, h)))));
    EXPECT_EQ(counts.width(counts.levels() - 1), 1);
    EXPECT_EQ(counts.height(counts.levels() - 1), 1);
    for (int level = 0; level < counts.levels(); ++level) {
      EXPECT_EQ(counts.width(level), std::max(1, w >> level));
      EXPECT_EQ(counts.height(level), std::max(1, h >> level));
      std::vector<int> covered(static_cast<size_t>(w) * h, 0);
      for (int y = 0; y < counts.height(level); ++y) {
        for (int x = 0; x < counts.width(level); ++x) {
          int x0, y0, x1, y1;
          counts.Block(level, x, y, &x0, &y0, &x1, &y1);
          std::array<double, kHoleCountChannels> sum{};
          for (int by = y0; by < y1; ++by) {
            for (int bx = x0; bx < x1; ++bx) {
              ++covered[static_cast<size_t>(by) * w + bx];
              const auto c = CountsByDefinition(mask, bx, by);
              for (int k = 0; k < kHoleCountChannels; ++k) sum[k] += c[k];
            }
          }
          const HoleTexel t = HoleTexelAt(counts, level, x, y);
          EXPECT_EQ(t.texels, (x1 - x0) * (y1 - y0));
          for (int k = 0; k < kHoleCountChannels; ++k) {
            EXPECT_EQ(t.counts[k], sum[k]) << "level " << level;
          }
        }
      }
      // The blocks of a level tile the base exactly once.
      for (int c : covered) EXPECT_EQ(c, 1) << w << "x" << h << " l" << level;
    }
  }
}

TEST(HolePyramidTest, PowerOfTwoBlocksHoldFourToTheLevelTexels) {
  // 32 x 8: T = 4^l until the height is 1, then the blocks grow in x only.
  const CountPyramid counts = HoleCountsFromMask(RandomMask(32, 8, 0.3, 1));
  const double expected[] = {1, 4, 16, 64, 128, 256};
  ASSERT_EQ(counts.levels(), 6);
  for (int level = 0; level < counts.levels(); ++level) {
    EXPECT_EQ(counts.Texels(level, 0, 0), expected[level]) << level;
  }
}

// Issue 6: Algorithm 3.1 equals the ground truth for |rx|, |ry| <= 1 at
// every level, within the truth's integration error.
TEST(Algorithm31Test, EqualsGroundTruthAtEveryLevel) {
  const std::vector<glm::dvec2> offsets = {
      {0.83, 0.41}, {-0.6, 0.95}, {-1.0, -1.0}, {0.37, -0.77},
      {1.0, 0.0},   {0.0, -0.55}, {0.999, 0.2}, {-0.25, 0.15}};
  for (const auto& [w, h] :
       std::vector<std::pair<int, int>>{{16, 16}, {12, 10}}) {
    const Mask mask = RandomMask(w, h, 0.45, 31 + w * h);
    const HoleTexture texture = AnalyzeMask(mask, false);
    for (const glm::dvec2& r : offsets) {
      const std::vector<HoleRatios> truths = TexelTruths(mask, r);
      double worst = 0.0;
      for (int level = 0; level < texture.counts.levels(); ++level) {
        for (int y = 0; y < texture.counts.height(level); ++y) {
          for (int x = 0; x < texture.counts.width(level); ++x) {
            int x0, y0, x1, y1;
            texture.counts.Block(level, x, y, &x0, &y0, &x1, &y1);
            const HoleRatios truth = BlockTruth(truths, mask, x0, y0, x1, y1);
            const HoleRatios alg = EvaluateTexel(
                texture, HoleMethod::kAlgorithm31, level, x, y, r);
            EXPECT_DOUBLE_EQ(alg.opaque, truth.opaque);
            EXPECT_NEAR(alg.occluded, truth.occluded, kTruthError)
                << "r " << r.x << "," << r.y << " level " << level << " texel "
                << x << "," << y;
            EXPECT_NEAR(alg.transparent, truth.transparent, kTruthError);
            worst = std::max(worst, std::abs(alg.occluded - truth.occluded));
          }
        }
      }
      // Level 0 holds texels where a missed wall or triangle costs up to
      // |rx| or |ry| / 2, far above the tolerance; the fit is much closer.
      EXPECT_LT(worst, 0.5 * kTruthError) << r.x << "," << r.y;
    }
  }
}

TEST(Algorithm31Test, AllOpaqueAndAllTransparentMasks) {
  Mask opaque = RandomMask(6, 4, 1.0, 1);
  Mask clear = RandomMask(6, 4, 0.0, 1);
  const HoleTexture t_opaque = AnalyzeMask(opaque, true);
  const HoleTexture t_clear = AnalyzeMask(clear, true);
  for (const glm::dvec2& r : std::vector<glm::dvec2>{
           {0.0, 0.0}, {0.7, -0.3}, {-1.0, 1.0}, {5.0, 2.5}, {-30.0, 0.1}}) {
    for (HoleMethod method :
         {HoleMethod::kAlgorithm31, HoleMethod::kExtension}) {
      for (int level = 0; level < t_opaque.counts.levels(); ++level) {
        const HoleRatios a = EvaluateTexel(t_opaque, method, level, 0, 0, r);
        EXPECT_EQ(a.opaque, 1.0);
        EXPECT_EQ(a.occluded, 0.0);
        EXPECT_EQ(a.transparent, 0.0);
        const HoleRatios b = EvaluateTexel(t_clear, method, level, 0, 0, r);
        EXPECT_EQ(b.opaque, 0.0);
        EXPECT_EQ(b.occluded, 0.0);
        EXPECT_EQ(b.transparent, 1.0);
      }
    }
    EXPECT_EQ(HoleTruthTile(opaque, r, 4).opaque, 1.0);
    EXPECT_EQ(HoleTruthTile(clear, r, 4).transparent, 1.0);
  }
}

TEST(Algorithm31Test, ViewOffsetFollowsSpec) {
  const glm::dvec3 wo = glm::normalize(glm::dvec3(0.3, -0.4, 0.5));
  const glm::dvec2 r = ViewOffset(2.0, wo);
  EXPECT_NEAR(r.x, -2.0 * 0.3 / 0.5, 1e-12);
  EXPECT_NEAR(r.y, 2.0 * 0.4 / 0.5, 1e-12);
  const glm::dvec2 below = ViewOffset(2.0, glm::dvec3(wo.x, wo.y, -wo.z));
  EXPECT_EQ(below, r);  // the far side sees the same offset
}

TEST(GroundTruthTest, StripesMatchTheClosedForm) {
  // One opaque column every 5 texels: a ray travelling rx >= 0 texels
  // sideways passes when it lands in the 4-texel gap at least rx before its
  // end: transmittance max(0, 4 - rx) / 5, whatever ry (rows are equal).
  const Mask mask = MaskFromRows({"....#", "....#", "....#"});
  for (double rx : {0.0, 0.4, 1.7, 3.2, 4.5, -2.6}) {
    for (double ry : {0.0, 0.9, -7.3, 25.0}) {
      const HoleRatios t = HoleTruthTile(mask, {rx, ry}, 64);
      EXPECT_NEAR(t.transparent, std::max(0.0, 4.0 - std::abs(rx)) / 5.0,
                  1.0 / 64)
          << rx << "," << ry;
      EXPECT_DOUBLE_EQ(t.opaque, 0.2);
    }
  }
}

TEST(GroundTruthTest, ShearedFootprintOverTheTileEqualsTheTile) {
  // A parallelogram sheared by whole tiles covers the torus once.
  const Mask mask = RandomMask(8, 6, 0.4, 5);
  const glm::dvec2 r(1.6, -2.3);
  Footprint sheared;
  sheared.edge_u = {8.0, 0.0};
  sheared.edge_v = {16.0, 6.0};
  sheared.samples_u = 8 * 48;
  sheared.samples_v = 6 * 48;
  const HoleRatios a = HoleTruth(mask, r, sheared);
  const HoleRatios b = HoleTruthTile(mask, r, 48);
  EXPECT_NEAR(a.transparent, b.transparent, 0.01);
  EXPECT_NEAR(a.opaque, b.opaque, 0.01);
}

TEST(ExtensionTest, IsAlgorithm31WithinOneTexel) {
  const Mask mask = RandomMask(12, 10, 0.4, 77);
  const HoleTexture texture = AnalyzeMask(mask, true);
  for (const glm::dvec2& r : std::vector<glm::dvec2>{
           {0.5, 0.5}, {-1.0, 0.3}, {0.2, -0.9}, {-0.7, -0.7}}) {
    for (int level = 0; level < texture.counts.levels(); ++level) {
      for (int y = 0; y < texture.counts.height(level); ++y) {
        for (int x = 0; x < texture.counts.width(level); ++x) {
          const HoleRatios a =
              EvaluateTexel(texture, HoleMethod::kAlgorithm31, level, x, y, r);
          const HoleRatios e =
              EvaluateTexel(texture, HoleMethod::kExtension, level, x, y, r);
          EXPECT_NEAR(e.occluded, a.occluded, 1e-12);
        }
      }
    }
  }
}

TEST(ExtensionTest, ExactPerTexelInRectangularHoles) {
  // 5 x 3 holes between 1-texel bars, offsets up to 4 texels.
  const Mask mask = MaskFromRows({".....#", ".....#", ".....#", "######"});
  const HoleTexture texture = AnalyzeMask(mask, true);
  for (const glm::dvec2& r : std::vector<glm::dvec2>{
           {2.3, 0.4}, {-3.6, 1.7}, {1.2, -2.2}, {-0.4, -2.9}, {4.2, 0.0}}) {
    const std::vector<HoleRatios> truths = TexelTruths(mask, r);
    for (int y = 0; y < mask.height; ++y) {
      for (int x = 0; x < mask.width; ++x) {
        const HoleRatios e =
            EvaluateTexel(texture, HoleMethod::kExtension, 0, x, y, r);
        EXPECT_NEAR(e.transparent, truths[y * mask.width + x].transparent,
                    4.0 / kSamples)
            << r.x << "," << r.y << " texel " << x << "," << y;
      }
    }
  }
}

TEST(ExtensionTest, DiagonalObstacleOfAnOpenField) {
  // One opaque texel in a 9 x 9 tile: from texel (2, 2) the diagonal meets
  // it after 2 transparent texels while the axial runs see nothing.
  std::vector<std::string> rows(9, ".........");
  rows[5][5] = '#';
  const Mask mask = MaskFromRows(rows);
  const HoleTexture texture = AnalyzeMask(mask, true);
  const glm::dvec2 r(3.1, 2.8);
  const HoleRatios truth = HoleTruth(mask, r, BlockFootprint(2, 2, 3, 3, 256));
  const HoleRatios e =
      EvaluateTexel(texture, HoleMethod::kExtension, 0, 2, 2, r);
  EXPECT_GT(truth.occluded, 0.3);
  EXPECT_NEAR(e.occluded, truth.occluded, 0.01);
}

// Issue 6: on the thesis's mosquito net (5 x 5 holes, 1-texel bars) at
// h = 2 and 60 degrees the extension is at least 3x more accurate.
TEST(ExtensionTest, ThreeTimesMoreAccurateOnFiveByFiveHoles) {
  const Mask period = SquareHoleMask(5, 1);
  // Six periods per side: coarse levels mix parts of several holes.
  Mask mask;
  mask.width = mask.height = 36;
  for (int y = 0; y < 36; ++y) {
    for (int x = 0; x < 36; ++x) mask.opaque.push_back(period.Opaque(x, y));
  }
  const HoleTexture texture = AnalyzeMask(mask, true);
  for (int level = 0; level < texture.counts.levels(); ++level) {
    const LevelTexels texels = GatherLevel(texture, level);
    double se_alg = 0.0, se_ext = 0.0;
    for (double phi = 0.0; phi < 360.0; phi += 15.0) {
      const glm::dvec2 r = ViewOffset(2.0, View(60.0, phi));
      const double truth = HoleTruthTile(period, r, 64).transparent;
      se_alg += Sqr(
          TileRatios(texels, HoleMethod::kAlgorithm31, r).transparent - truth);
      se_ext += Sqr(TileRatios(texels, HoleMethod::kExtension, r).transparent -
                    truth);
    }
    std::printf("level %d: rms error Algorithm 3.1 %.4f, extension %.4f\n",
                level, std::sqrt(se_alg / 24), std::sqrt(se_ext / 24));
    EXPECT_GE(std::sqrt(se_alg), 3.0 * std::sqrt(se_ext)) << "level " << level;
  }
}

// Irregular holes: round holes of random radii carved out of an opaque
// 64 x 64 tile (a curtain), and random texels (35 % opaque). The extension
// is approximate there (docs/holes.md) but still far closer than Algorithm
// 3.1 once views travel more than a texel.
Mask CurtainMask() {
  Mask mask = RandomMask(64, 64, 1.0, 1);
  Random random(12);
  for (int k = 0; k < 14; ++k) {
    const double cx = 64 * random.Uniform(), cy = 64 * random.Uniform();
    const double radius = 1.5 + 3.5 * random.Uniform();
    for (int y = 0; y < 64; ++y) {
      for (int x = 0; x < 64; ++x) {
        const double dx =
            std::min(std::abs(x + 0.5 - cx), 64 - std::abs(x + 0.5 - cx));
        const double dy =
            std::min(std::abs(y + 0.5 - cy), 64 - std::abs(y + 0.5 - cy));
        if (dx * dx + dy * dy < radius * radius) mask.opaque[y * 64 + x] = 0;
      }
    }
  }
  return mask;
}

TEST(ExtensionTest, CloserThanAlgorithm31OnIrregularMasks) {
  const struct {
    const char* name;
    Mask mask;
  } masks[] = {{"random", RandomMask(64, 64, 0.35, 21)},
               {"curtain", CurtainMask()}};
  for (const auto& [name, mask] : masks) {
    const HoleTexture texture = AnalyzeMask(mask, true);
    const Footprint tile = TileFootprint(mask, 250000);
    for (double h : {0.5, 2.0}) {
      for (int level : {0, texture.counts.levels() - 1}) {
        const LevelTexels texels = GatherLevel(texture, level);
        double se_alg = 0.0, se_ext = 0.0;
        int views = 0;
        for (double theta : {30.0, 45.0, 60.0, 70.0}) {
          for (double phi : {0.0, 30.0, 45.0, 200.0}) {
            const glm::dvec2 r = ViewOffset(h, View(theta, phi));
            const double truth = HoleTruth(mask, r, tile).transparent;
            se_alg += Sqr(
                TileRatios(texels, HoleMethod::kAlgorithm31, r).transparent -
                truth);
            se_ext +=
                Sqr(TileRatios(texels, HoleMethod::kExtension, r).transparent -
                    truth);
            ++views;
          }
        }
        const double alg = std::sqrt(se_alg / views);
        const double ext = std::sqrt(se_ext / views);
        std::printf(
            "%s h = %g level %d: rms error Algorithm 3.1 %.4f, "
            "extension %.4f\n",
            name, h, level, alg, ext);
        EXPECT_GE(alg, 2.0 * ext) << name << " h " << h << " level " << level;
      }
    }
  }
}

TEST(TrilinearTest, InterpolatesTexelsAndLevels) {
  const Mask mask = RandomMask(16, 8, 0.4, 3);
  const HoleTexture texture = AnalyzeMask(mask, true);
  const glm::dvec2 r(0.6, -0.35);
  for (HoleMethod method : {HoleMethod::kAlgorithm31, HoleMethod::kExtension}) {
    // At a texel centre of level 1, with an integer lod: that texel.
    const HoleRatios centre = SampleTrilinear(
        texture, method, {2.0 * 3 + 1.0, 2.0 * 2 + 1.0}, 1.0, r);
    EXPECT_NEAR(centre.occluded,
                EvaluateTexel(texture, method, 1, 3, 2, r).occluded, 1e-12);
    // Halfway between two level-0 texel centres: their mean.
    const HoleRatios between =
        SampleTrilinear(texture, method, {5.0, 3.5}, 0.0, r);
    EXPECT_NEAR(between.transparent,
                0.5 * (EvaluateTexel(texture, method, 0, 4, 3, r).transparent +
                       EvaluateTexel(texture, method, 0, 5, 3, r).transparent),
                1e-12);
    // lod between two levels: linear between the two levels.
    const glm::dvec2 p(6.3, 2.2);
    const HoleRatios mixed = SampleTrilinear(texture, method, p, 1.25, r);
    EXPECT_NEAR(
        mixed.transparent,
        0.75 * SampleTrilinear(texture, method, p, 1.0, r).transparent +
            0.25 * SampleTrilinear(texture, method, p, 2.0, r).transparent,
        1e-12);
    // The texture wraps: a shift by the tile size changes nothing.
    EXPECT_NEAR(SampleTrilinear(texture, method, {0.1, 7.9}, 0.5, r).occluded,
                SampleTrilinear(texture, method, {16.1, -0.1}, 0.5, r).occluded,
                1e-12);
    // Beyond the top level: the 1 x 1 level, i.e. the tile.
    EXPECT_NEAR(SampleTrilinear(texture, method, p, 99.0, r).transparent,
                EvaluateTile(texture, method, texture.counts.levels() - 1, r)
                    .transparent,
                1e-12);
  }
}

}  // namespace
}  // namespace clothfit
