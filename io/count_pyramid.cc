#include "io/count_pyramid.h"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>

#include "models/mip_levels.h"

namespace clothfit {
namespace {

// dst (w1 x h1, zeroed) += the ROUND_DOWN 2 x 2 sums of src (w0 x h0).
// kFixed > 0 makes the channel count a compile-time constant (unrolled
// inner loops for the nine hole counts: the speed target is the pyramid
// of a 4096 x 4096 mask); 0 uses `channels`.
template <int kFixed, typename Src>
void SumLevelImpl(const Src* src, int w0, int h0, int channels, int w1, int h1,
                  int32_t* dst) {
  const int n = kFixed > 0 ? kFixed : channels;
  const size_t src_row = static_cast<size_t>(w0) * n;
  // The regular part: 2 x 2 blocks of rows and columns [0, 2 w1) x [0,
  // 2 h1), four texels added straight into each output texel.
  const int pairs_x = w0 >= 2 ? w1 : 0, pairs_y = h0 >= 2 ? h1 : 0;
  for (int y = 0; y < pairs_y; ++y) {
    const Src* a = src + 2 * y * src_row;
    const Src* b = a + src_row;
    int32_t* d = dst + static_cast<size_t>(y) * w1 * n;
    for (int x = 0; x < pairs_x; ++x, a += 2 * n, b += 2 * n, d += n) {
      for (int c = 0; c < n; ++c) d[c] = a[c] + a[n + c] + b[c] + b[n + c];
    }
  }
  // What is left over (an odd last column or row, or a side of 1) joins the
  // last output column or row.
  for (int y = 0; y < h0; ++y) {
    const int py = std::min(y >> 1, h1 - 1);
    const int first_x = y < 2 * pairs_y ? 2 * pairs_x : 0;
    const Src* s = src + y * src_row + static_cast<size_t>(first_x) * n;
    int32_t* row = dst + static_cast<size_t>(py) * w1 * n;
    for (int x = first_x; x < w0; ++x, s += n) {
      int32_t* d = row + static_cast<size_t>(std::min(x >> 1, w1 - 1)) * n;
      for (int c = 0; c < n; ++c) d[c] += s[c];
    }
  }
}

template <typename Src>
void SumLevel(const Src* src, int w0, int h0, int channels, int w1, int h1,
              int32_t* dst) {
  if (channels == 9) {
    SumLevelImpl<9>(src, w0, h0, channels, w1, h1, dst);
  } else {
    SumLevelImpl<0>(src, w0, h0, channels, w1, h1, dst);
  }
}

}  // namespace

CountPyramid::CountPyramid(int width, int height, int channels,
                           std::vector<uint8_t> base)
    : channels_(channels),
      width_(width),
      height_(height),
      base_(std::move(base)) {
  if (width < 1 || height < 1 || channels < 1 ||
      base_.size() != static_cast<size_t>(width) * height * channels) {
    throw std::invalid_argument(
        "CountPyramid: inconsistent base of " + std::to_string(base_.size()) +
        " values for " + std::to_string(width) + " x " +
        std::to_string(height) + " x " + std::to_string(channels));
  }
  const int levels = MipLevelCount(width, height);
  upper_.resize(levels - 1);
  for (int level = 1; level < levels; ++level) {
    const int w0 = MipLevelSize(width, level - 1),
              h0 = MipLevelSize(height, level - 1);
    const int w1 = MipLevelSize(width, level), h1 = MipLevelSize(height, level);
    std::vector<int32_t>& dst = upper_[level - 1];
    dst.assign(static_cast<size_t>(w1) * h1 * channels, 0);
    if (level == 1) {
      SumLevel(base_.data(), w0, h0, channels, w1, h1, dst.data());
    } else {
      SumLevel(upper_[level - 2].data(), w0, h0, channels, w1, h1, dst.data());
    }
  }
}

int CountPyramid::width(int level) const { return MipLevelSize(width_, level); }
int CountPyramid::height(int level) const {
  return MipLevelSize(height_, level);
}

void CountPyramid::Counts(int level, int x, int y, double* out) const {
  const size_t index = (static_cast<size_t>(y) * width(level) + x) * channels_;
  if (level == 0) {
    for (int c = 0; c < channels_; ++c) out[c] = base_[index + c];
  } else {
    const int32_t* values = upper_[level - 1].data() + index;
    for (int c = 0; c < channels_; ++c) out[c] = values[c];
  }
}

void CountPyramid::Block(int level, int x, int y, int* x0, int* y0, int* x1,
                         int* y1) const {
  *x0 = x << level;
  *y0 = y << level;
  *x1 = x == width(level) - 1 ? width_ : (x + 1) << level;
  *y1 = y == height(level) - 1 ? height_ : (y + 1) << level;
}

double CountPyramid::Texels(int level, int x, int y) const {
  int x0, y0, x1, y1;
  Block(level, x, y, &x0, &y0, &x1, &y1);
  return static_cast<double>(x1 - x0) * static_cast<double>(y1 - y0);
}

}  // namespace clothfit
