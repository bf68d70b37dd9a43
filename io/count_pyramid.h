// A mip pyramid of per-texel counts that add up: level 0 holds small
// integer counts per texel (interleaved channels), level l + 1 sums 2 x 2
// blocks of level l, down to 1 x 1.
//
// Sizes that are not powers of two follow OpenEXR's MIPMAP_LEVELS /
// ROUND_DOWN (models/mip_levels.h): level l is max(1, W >> l) x
// max(1, H >> l); the last column
// (row) of a level also sums what is left over when the level below has an
// odd width (height). So texel x of level l covers base columns
// [x 2^l, (x + 1) 2^l), except the last one, which reaches W; T (the
// number of base texels a texel sums) is 4^l for power-of-two masks and
// the block's area otherwise. Counts are exact integers, each level above
// the base stored in the narrowest unsigned type that holds its largest
// possible count (the base's largest value times the level's largest T); a
// base of 0/1 counts in up to 64 channels may come as one bit per count.
// The 64 run counts of a 4096 x 4096 mask take 0.5 GB so, instead of 2.5 GB
// with a byte per base count and 32-bit levels.
#pragma once

#include <cstddef>
#include <cstdint>
#include <variant>
#include <vector>

namespace clothfit {

class CountPyramid {
 public:
  CountPyramid() = default;
  // Builds every level from the base counts base[(y * width + x) *
  // channels + c]. width, height >= 1. Throws std::invalid_argument when a
  // level's counts could exceed 32 bits.
  CountPyramid(int width, int height, int channels, std::vector<uint8_t> base);
  // The same from a base of 0/1 counts, one word per texel: channel c of
  // texel (x, y) is bit c of bits[y * width + x]. channels <= 64.
  CountPyramid(int width, int height, int channels, std::vector<uint64_t> bits);

  bool empty() const { return channels_ == 0; }
  int channels() const { return channels_; }
  int levels() const { return static_cast<int>(levels_.size()); }
  int width(int level) const;
  int height(int level) const;

  // The counts of texel (x, y) of `level` (0 <= x < width(level), ...),
  // written to out[0 .. channels()).
  void Counts(int level, int x, int y, double* out) const;
  // The base texels [x0, x1) x [y0, y1) that texel (x, y) of `level` sums.
  void Block(int level, int x, int y, int* x0, int* y0, int* x1, int* y1) const;
  // Their number T.
  double Texels(int level, int x, int y) const;

  // The counts of row y of `level`, channel c of texel x written to
  // rows[c][x] (rows[c] holds width(level) values).
  void RowCounts(int level, int y, float* const* rows) const;

  // The bits each count of `level` takes (1, 8, 16 or 32).
  int BitsPerCount(int level) const;

 private:
  struct BaseBits {
    std::vector<uint64_t> words;  // one per texel, bit c = channel c
  };
  using LevelData = std::variant<BaseBits, std::vector<uint8_t>,
                                 std::vector<uint16_t>, std::vector<uint32_t>>;
  // Checks the sizes (`values` base values given).
  void CheckBase(size_t values, size_t expected) const;
  // Levels 1, 2 ... from levels_[0], whose counts are at most max_base.
  void BuildLevels(uint64_t max_base);

  int channels_ = 0;
  int width_ = 0, height_ = 0;
  std::vector<LevelData> levels_;  // level 0 first, channels interleaved
};

}  // namespace clothfit
