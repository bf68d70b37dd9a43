// Count pyramids: every level sums its blocks of the base exactly, also
// where the counts pass 8 and 16 bits; each level takes the narrowest type
// its largest block allows; a base of one bit per count gives the same
// pyramid as a byte per count.
#include "io/count_pyramid.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <stdexcept>
#include <utility>
#include <vector>

namespace clothfit {
namespace {

// The sum of base channel c over the base texels that texel (x, y) of
// `level` covers, by brute force.
double BlockSum(const CountPyramid& p, const std::vector<uint8_t>& base,
                int level, int x, int y, int c) {
  int x0, y0, x1, y1;
  p.Block(level, x, y, &x0, &y0, &x1, &y1);
  double sum = 0.0;
  for (int by = y0; by < y1; ++by) {
    for (int bx = x0; bx < x1; ++bx) {
      sum +=
          base[(static_cast<size_t>(by) * p.width(0) + bx) * p.channels() + c];
    }
  }
  return sum;
}

// Every texel of every level equals its block sum.
void ExpectBlockSums(const CountPyramid& p, const std::vector<uint8_t>& base) {
  std::vector<double> counts(p.channels());
  for (int level = 0; level < p.levels(); ++level) {
    for (int y = 0; y < p.height(level); ++y) {
      for (int x = 0; x < p.width(level); ++x) {
        p.Counts(level, x, y, counts.data());
        for (int c = 0; c < p.channels(); ++c) {
          ASSERT_EQ(counts[c], BlockSum(p, base, level, x, y, c))
              << "level " << level << " texel " << x << "," << y << " c " << c;
        }
      }
    }
  }
}

std::vector<uint8_t> RandomBase(size_t n, int max, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_int_distribution<int> value(0, max);
  std::vector<uint8_t> base(n);
  for (uint8_t& v : base) v = static_cast<uint8_t>(value(random));
  return base;
}

TEST(CountPyramidTest, LevelsSumTheirBlocksBeyondEightAndSixteenBits) {
  // 255 everywhere: level 1 already needs 16 bits, level 5 (blocks of 32 x
  // 32 and more) 32 bits; odd sizes give larger last blocks.
  for (const auto& [w, h] : {std::pair{301, 263}, std::pair{64, 64}}) {
    const std::vector<uint8_t> full(static_cast<size_t>(w) * h * 2, 255);
    const CountPyramid p(w, h, 2, full);
    ExpectBlockSums(p, full);
    EXPECT_EQ(p.BitsPerCount(0), 8);
    EXPECT_EQ(p.BitsPerCount(1), 16);
    EXPECT_EQ(p.BitsPerCount(5), 32);
    double top[2];
    p.Counts(p.levels() - 1, 0, 0, top);
    EXPECT_EQ(top[1], 255.0 * w * h);
  }
  // Random counts 0..2 in three channels.
  const std::vector<uint8_t> base = RandomBase(37 * 20 * 3, 2, 5);
  ExpectBlockSums(CountPyramid(37, 20, 3, base), base);
}

TEST(CountPyramidTest, EachLevelTakesTheNarrowestTypeOfItsLargestBlock) {
  // 0/1 counts, 64 x 64: levels 1-3 hold at most 4, 16, 64 (8 bits), level
  // 4 up to 256 (16 bits).
  const CountPyramid even(64, 64, 1, std::vector<uint8_t>(64 * 64, 1));
  const int even_bits[] = {8, 8, 8, 8, 16, 16, 16};
  ASSERT_EQ(even.levels(), 7);
  for (int level = 0; level < 7; ++level) {
    EXPECT_EQ(even.BitsPerCount(level), even_bits[level]) << level;
  }
  // 63 x 63: the last block of level 3 is 15 x 15 = 225 texels (8 bits), of
  // level 4 31 x 31 = 961 (16 bits).
  const CountPyramid odd(63, 63, 1, std::vector<uint8_t>(63 * 63, 1));
  EXPECT_EQ(odd.Texels(3, 6, 6), 225.0);
  EXPECT_EQ(odd.BitsPerCount(3), 8);
  EXPECT_EQ(odd.BitsPerCount(4), 16);
  // All zero: 8 bits throughout.
  const CountPyramid zero(64, 64, 1, std::vector<uint8_t>(64 * 64, 0));
  EXPECT_EQ(zero.BitsPerCount(zero.levels() - 1), 8);
}

TEST(CountPyramidTest, BitBaseEqualsByteBase) {
  for (const int channels : {64, 5}) {
    for (const auto& [w, h] :
         {std::pair{33, 17}, std::pair{13, 7}, std::pair{1, 9}, std::pair{8, 1},
          std::pair{1, 1}}) {
      const size_t texels = static_cast<size_t>(w) * h;
      const std::vector<uint8_t> bytes =
          RandomBase(texels * channels, 1, static_cast<unsigned>(w * h));
      std::vector<uint64_t> bits(texels, 0);
      for (size_t t = 0; t < texels; ++t) {
        for (int c = 0; c < channels; ++c) {
          bits[t] |= uint64_t{bytes[t * channels + c]} << c;
        }
      }
      const CountPyramid from_bits(w, h, channels, bits);
      EXPECT_EQ(from_bits.BitsPerCount(0), 1);
      ExpectBlockSums(from_bits, bytes);
      // Rows as floats equal the texels' counts, at every level.
      std::vector<double> counts(channels);
      for (int level = 0; level < from_bits.levels(); ++level) {
        const int lw = from_bits.width(level);
        std::vector<std::vector<float>> rows(channels, std::vector<float>(lw));
        std::vector<float*> pointers;
        for (std::vector<float>& row : rows) pointers.push_back(row.data());
        for (int y = 0; y < from_bits.height(level); ++y) {
          from_bits.RowCounts(level, y, pointers.data());
          for (int x = 0; x < lw; ++x) {
            from_bits.Counts(level, x, y, counts.data());
            for (int c = 0; c < channels; ++c) {
              ASSERT_EQ(rows[c][x], counts[c]) << level << " " << x << "," << y;
            }
          }
        }
      }
    }
  }
}

TEST(CountPyramidTest, InconsistentBasesAreRefused) {
  EXPECT_THROW(CountPyramid(4, 4, 2, std::vector<uint8_t>(31)),
               std::invalid_argument);
  EXPECT_THROW(CountPyramid(4, 4, 65, std::vector<uint64_t>(16)),
               std::invalid_argument);
  EXPECT_THROW(CountPyramid(4, 4, 8, std::vector<uint64_t>(15)),
               std::invalid_argument);
  EXPECT_THROW(CountPyramid(0, 4, 8, std::vector<uint64_t>()),
               std::invalid_argument);
}

}  // namespace
}  // namespace clothfit
