// The virtual gonioreflectometer (data_synthetic/virtual_gonio.h): table
// layout, determinism, holes, shadowing and thread colours on small grids.
#include "data_synthetic/virtual_gonio.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "data_synthetic/weave_surface_internal.h"
#include "io/input_error.h"
#include "models/math.h"

namespace clothfit {
namespace {

VirtualGonioOptions Small(WeavePattern pattern = WeavePattern::kPlain) {
  VirtualGonioOptions options;
  options.pattern = pattern;
  options.texels = 4;
  options.directions = 4;
  options.supersample = 2;
  options.grid = 256;
  return options;
}

size_t RowIndex(int texel, int view, int light, int pairs) {
  return (static_cast<size_t>(texel) * pairs + view) * pairs + light;
}

// Mean of (r, g, b) over all rows of texel (s, t).
glm::dvec3 TexelMean(const MeasurementTable& table, int s, int t, int texels,
                     int pairs) {
  glm::dvec3 sum(0.0);
  const size_t begin = RowIndex(t * texels + s, 0, 0, pairs);
  const size_t count = static_cast<size_t>(pairs) * pairs;
  for (size_t k = begin; k < begin + count; ++k) sum += table.rows[k].value;
  return sum / static_cast<double>(count);
}

// The glossy band's normaliser: the integral over the light of max(n.l, 0)
// sin(t, h)^32 on a flat facet is largest at the view along the normal,
// where it is kGlossyBandAlbedo, so the shading's albedo is at most
// (1 - glossy) c + glossy tint <= 1.
TEST(VirtualGonioTest, GlossyBandNormaliserIsTheBandsLargestAlbedo) {
  const int n = 300;
  auto band = [&](const glm::dvec3& v) {
    double sum = 0.0;
    for (int i = 0; i < n; ++i) {
      const double theta = (i + 0.5) / n * 0.5 * kPi;
      for (int j = 0; j < 2 * n; ++j) {
        const double phi = (j + 0.5) / (2 * n) * 2.0 * kPi;
        const glm::dvec3 l(std::sin(theta) * std::cos(phi),
                           std::sin(theta) * std::sin(phi), std::cos(theta));
        const glm::dvec3 h = glm::normalize(l + v);
        sum +=
            std::pow(1.0 - h.x * h.x, 0.5 * weave_internal::kGlossyExponent) *
            l.z * std::sin(theta) * (0.5 * kPi / n) * (kPi / n);
      }
    }
    return sum;
  };
  EXPECT_NEAR(band(glm::dvec3(0.0, 0.0, 1.0)),
              weave_internal::kGlossyBandAlbedo, 2e-3);
  for (double deg : {20.0, 45.0, 70.0, 89.0}) {
    const double t = deg * kPi / 180.0;
    for (const glm::dvec3& v : {glm::dvec3(std::sin(t), 0.0, std::cos(t)),
                                glm::dvec3(0.0, std::sin(t), std::cos(t))}) {
      EXPECT_LT(band(v), weave_internal::kGlossyBandAlbedo) << deg;
    }
  }
}

TEST(VirtualGonioTest, ParsesPatternNames) {
  WeavePattern pattern = WeavePattern::kPlain;
  EXPECT_TRUE(ParseWeavePattern("satin", &pattern));
  EXPECT_EQ(pattern, WeavePattern::kSatin);
  EXPECT_TRUE(ParseWeavePattern("knit", &pattern));
  EXPECT_EQ(pattern, WeavePattern::kKnit);
  EXPECT_TRUE(ParseWeavePattern("plain", &pattern));
  EXPECT_EQ(pattern, WeavePattern::kPlain);
  EXPECT_FALSE(ParseWeavePattern("twill", &pattern));
  EXPECT_FALSE(ParseWeavePattern("", &pattern));
  EXPECT_EQ(pattern, WeavePattern::kPlain);  // unchanged on failure
  EXPECT_STREQ(WeavePatternName(WeavePattern::kSatin), "satin");
}

TEST(VirtualGonioTest, TableLayoutAndMetadata) {
  VirtualGonioOptions options = Small();
  options.texels = 3;
  options.directions = 3;
  const MeasurementTable table = MeasureVirtualGonio(options);
  const int pairs = 9;
  ASSERT_EQ(table.rows.size(), static_cast<size_t>(3 * 3 * 9 * 9));
  EXPECT_EQ(table.quantity, Quantity::kCosineWeighted);
  EXPECT_EQ(table.channels, 3);
  EXPECT_EQ(table.direction_columns, DirectionColumns::kVectors);
  EXPECT_TRUE(table.has_texels);
  EXPECT_TRUE(table.has_alpha);
  EXPECT_EQ(table.Meta("pattern").value_or(""), "plain");
  EXPECT_EQ(table.Meta("sample").value_or(""),
            "virtual gonioreflectometer: plain weave, 3x3 texels, 3x3 "
            "directions, seed 1");

  // The first texel's rows list the direction set: view-major, then light.
  std::vector<glm::dvec3> dirs;
  for (int light = 0; light < pairs; ++light) {
    dirs.push_back(table.rows[light].wi);
  }
  const double min_cos = std::cos(Radians(85.0));
  for (int i = 0; i < pairs; ++i) {
    EXPECT_NEAR(glm::length(dirs[i]), 1.0, 1e-12);
    EXPECT_GT(dirs[i].z, min_cos);
    EXPECT_LT(dirs[i].z, 1.0);
    for (int j = 0; j < i; ++j) EXPECT_GT(glm::length(dirs[i] - dirs[j]), 0.1);
  }
  for (int t = 0; t < 3; ++t) {
    for (int s = 0; s < 3; ++s) {
      for (int view = 0; view < pairs; ++view) {
        for (int light = 0; light < pairs; ++light) {
          const TableRow& row =
              table.rows[RowIndex(t * 3 + s, view, light, pairs)];
          ASSERT_EQ(row.s, s);
          ASSERT_EQ(row.t, t);
          ASSERT_EQ(row.wi, dirs[light]);
          ASSERT_EQ(row.wo, dirs[view]);
          ASSERT_EQ(row.sigma, glm::dvec3(1.0));
          ASSERT_EQ(row.weight, 1.0);
        }
      }
    }
  }
}

TEST(VirtualGonioTest, RowCountIsTexelsSquaredTimesDirectionsToTheFourth) {
  for (WeavePattern pattern :
       {WeavePattern::kPlain, WeavePattern::kSatin, WeavePattern::kKnit}) {
    VirtualGonioOptions options = Small(pattern);
    options.texels = 2;
    options.directions = 3;
    EXPECT_EQ(MeasureVirtualGonio(options).rows.size(),
              static_cast<size_t>(2 * 2 * 3 * 3 * 3 * 3));
  }
}

TEST(VirtualGonioTest, ValuesFiniteNonNegativeAlphaPerView) {
  for (WeavePattern pattern :
       {WeavePattern::kPlain, WeavePattern::kSatin, WeavePattern::kKnit}) {
    const VirtualGonioOptions options = Small(pattern);
    const MeasurementTable table = MeasureVirtualGonio(options);
    const int pairs = 16;
    double total = 0.0;
    for (const TableRow& row : table.rows) {
      for (int c = 0; c < 3; ++c) {
        ASSERT_TRUE(std::isfinite(row.value[c]));
        ASSERT_GE(row.value[c], 0.0);
        total += row.value[c];
      }
      ASSERT_GE(row.alpha, 0.0);
      ASSERT_LE(row.alpha, 1.0);
      // alpha counts the 2 x 2 rays that hit: a multiple of 1/4.
      ASSERT_DOUBLE_EQ(row.alpha * 4.0, std::round(row.alpha * 4.0));
    }
    EXPECT_GT(total, 0.0);
    // The coverage belongs to the view: the same for every light.
    for (int texel = 0; texel < 16; ++texel) {
      for (int view = 0; view < pairs; ++view) {
        const double alpha = table.rows[RowIndex(texel, view, 0, pairs)].alpha;
        for (int light = 1; light < pairs; ++light) {
          ASSERT_EQ(table.rows[RowIndex(texel, view, light, pairs)].alpha,
                    alpha);
        }
      }
    }
  }
}

TEST(VirtualGonioTest, DeterministicFromSeed) {
  for (WeavePattern pattern :
       {WeavePattern::kPlain, WeavePattern::kSatin, WeavePattern::kKnit}) {
    VirtualGonioOptions options = Small(pattern);
    const MeasurementTable a = MeasureVirtualGonio(options);
    const MeasurementTable b = MeasureVirtualGonio(options);
    ASSERT_EQ(a.rows.size(), b.rows.size());
    for (size_t k = 0; k < a.rows.size(); ++k) {
      ASSERT_EQ(a.rows[k].value, b.rows[k].value) << k;
      ASSERT_EQ(a.rows[k].alpha, b.rows[k].alpha) << k;
    }
    options.seed = 2;
    const MeasurementTable c = MeasureVirtualGonio(options);
    ASSERT_EQ(a.rows.size(), c.rows.size());
    size_t different = 0;
    for (size_t k = 0; k < a.rows.size(); ++k) {
      different += a.rows[k].value != c.rows[k].value;
      ASSERT_EQ(a.rows[k].wi, c.rows[k].wi);  // the directions are fixed
    }
    EXPECT_GT(different, a.rows.size() / 2);
  }
}

TEST(VirtualGonioTest, IndependentOfWorkerCount) {
  VirtualGonioOptions options = Small(WeavePattern::kSatin);
  options.threads = 1;
  const MeasurementTable one = MeasureVirtualGonio(options);
  options.threads = 3;
  const MeasurementTable three = MeasureVirtualGonio(options);
  ASSERT_EQ(one.rows.size(), three.rows.size());
  for (size_t k = 0; k < one.rows.size(); ++k) {
    ASSERT_EQ(one.rows[k].value, three.rows[k].value) << k;
    ASSERT_EQ(one.rows[k].alpha, three.rows[k].alpha) << k;
  }
}

TEST(VirtualGonioTest, GapsBetweenThreadsAreHoles) {
  VirtualGonioOptions options = Small();
  options.gap = 0.12;
  const MeasurementTable open = MeasureVirtualGonio(options);
  int holes = 0;
  for (const TableRow& row : open.rows) holes += row.alpha < 1.0;
  EXPECT_GT(holes, 0);

  // Without gaps the warp and weft cover every point: no holes at all.
  for (WeavePattern pattern : {WeavePattern::kPlain, WeavePattern::kSatin}) {
    options = Small(pattern);
    options.gap = 0.0;
    const MeasurementTable closed = MeasureVirtualGonio(options);
    for (const TableRow& row : closed.rows) ASSERT_EQ(row.alpha, 1.0);
  }
}

TEST(VirtualGonioTest, LessLightAsTheLightDescends) {
  for (WeavePattern pattern :
       {WeavePattern::kPlain, WeavePattern::kSatin, WeavePattern::kKnit}) {
    const VirtualGonioOptions options = Small(pattern);
    const MeasurementTable table = MeasureVirtualGonio(options);
    const int n = options.directions;
    const int pairs = n * n;
    // Mean value per light ring (ring i: cos(theta) grows with i).
    std::vector<double> ring(n, 0.0);
    std::vector<double> cos_theta(n, 0.0);
    for (size_t k = 0; k < table.rows.size(); ++k) {
      const int light = static_cast<int>(k % pairs);
      const TableRow& row = table.rows[k];
      ring[light / n] += row.value.x + row.value.y + row.value.z;
      cos_theta[light / n] = row.wi.z;
    }
    for (int i = 1; i < n; ++i) {
      EXPECT_GT(cos_theta[i], cos_theta[i - 1]);
      EXPECT_GT(ring[i], ring[i - 1])
          << "pattern " << WeavePatternName(pattern);
    }
    // Grazing light: much less than near-normal light.
    EXPECT_LT(ring[0], 0.5 * ring[n - 1]);
  }
}

TEST(VirtualGonioTest, WarpAndWeftColoursShowUp) {
  // 2 x 2 texels on a plain weave: each texel holds one crossing. The warp
  // (reddish) is on top at crossings (0, 0) and (1, 1), the weft (bluish)
  // at (1, 0) and (0, 1).
  VirtualGonioOptions options = Small();
  options.texels = 2;
  const MeasurementTable table = MeasureVirtualGonio(options);
  const int pairs = options.directions * options.directions;
  auto redness = [&](int s, int t) {
    const glm::dvec3 mean = TexelMean(table, s, t, 2, pairs);
    return mean.x / mean.z;
  };
  EXPECT_GT(redness(0, 0), 1.2 * redness(1, 0));
  EXPECT_GT(redness(0, 0), 1.2 * redness(0, 1));
  EXPECT_GT(redness(1, 1), 1.2 * redness(1, 0));
  EXPECT_GT(redness(1, 1), 1.2 * redness(0, 1));
  EXPECT_GT(redness(0, 0), 1.0);
  EXPECT_LT(redness(1, 0), 1.0);

  // A warp-faced satin shows mostly warp.
  const MeasurementTable satin =
      MeasureVirtualGonio(Small(WeavePattern::kSatin));
  glm::dvec3 sum(0.0);
  for (const TableRow& row : satin.rows) sum += row.value;
  EXPECT_GT(sum.x, 1.2 * sum.z);
}

TEST(VirtualGonioTest, RejectsBadOptions) {
  auto expect_error = [](auto change) {
    VirtualGonioOptions options = Small();
    change(&options);
    EXPECT_THROW(MeasureVirtualGonio(options), InputError);
  };
  expect_error([](VirtualGonioOptions* o) { o->texels = 0; });
  expect_error([](VirtualGonioOptions* o) { o->directions = 0; });
  expect_error([](VirtualGonioOptions* o) { o->supersample = 0; });
  // 8^2 x 64^4 = 1.07e9 rows would not fit in memory: refused up front.
  expect_error([](VirtualGonioOptions* o) {
    o->texels = 8;
    o->directions = 64;
  });
  expect_error([](VirtualGonioOptions* o) { o->grid = 8; });
  expect_error([](VirtualGonioOptions* o) { o->thread_radius = 0.0; });
  expect_error([](VirtualGonioOptions* o) { o->gap = -0.1; });
  expect_error([](VirtualGonioOptions* o) { o->gap = 0.5; });
  expect_error([](VirtualGonioOptions* o) { o->glossy = -1.0; });
  expect_error([](VirtualGonioOptions* o) { o->threads = -1; });
}

}  // namespace
}  // namespace clothfit
