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
// the block's area otherwise. Counts are exact 32-bit integers.
#pragma once

#include <cstdint>
#include <vector>

namespace clothfit {

class CountPyramid {
 public:
  CountPyramid() = default;
  // Builds every level from the base counts base[(y * width + x) *
  // channels + c]. width, height >= 1.
  CountPyramid(int width, int height, int channels, std::vector<uint8_t> base);

  bool empty() const { return channels_ == 0; }
  int channels() const { return channels_; }
  int levels() const { return static_cast<int>(upper_.size()) + 1; }
  int width(int level) const;
  int height(int level) const;

  // The counts of texel (x, y) of `level` (0 <= x < width(level), ...),
  // written to out[0 .. channels()).
  void Counts(int level, int x, int y, double* out) const;
  // The base texels [x0, x1) x [y0, y1) that texel (x, y) of `level` sums.
  void Block(int level, int x, int y, int* x0, int* y0, int* x1, int* y1) const;
  // Their number T.
  double Texels(int level, int x, int y) const;

  // Raw data: level 0 (uint8) and levels >= 1 (int32), interleaved.
  const std::vector<uint8_t>& base() const { return base_; }
  const std::vector<int32_t>& level_data(int level) const {
    return upper_[level - 1];
  }

 private:
  int channels_ = 0;
  int width_ = 0, height_ = 0;
  std::vector<uint8_t> base_;
  std::vector<std::vector<int32_t>> upper_;  // levels 1, 2, ...
};

}  // namespace clothfit
