#include "io/count_pyramid.h"

#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include "models/mip_levels.h"

namespace clothfit {
namespace {

// dst (w1 x h1, zeroed) += the ROUND_DOWN 2 x 2 sums of src (w0 x h0); the
// caller has checked that the sums fit Dst.
// kFixed > 0 makes the channel count a compile-time constant (unrolled
// inner loops for the nine hole counts and the 64 run counts: the speed
// target is the pyramid of a 4096 x 4096 mask); 0 uses `channels`.
template <int kFixed, typename Src, typename Dst>
void SumLevelImpl(const Src* src, int w0, int h0, int channels, int w1, int h1,
                  Dst* dst) {
  const int n = kFixed > 0 ? kFixed : channels;
  const size_t src_row = static_cast<size_t>(w0) * n;
  // The regular part: 2 x 2 blocks of rows and columns [0, 2 w1) x [0,
  // 2 h1), four texels added straight into each output texel.
  const int pairs_x = w0 >= 2 ? w1 : 0, pairs_y = h0 >= 2 ? h1 : 0;
  for (int y = 0; y < pairs_y; ++y) {
    const Src* a = src + 2 * y * src_row;
    const Src* b = a + src_row;
    Dst* d = dst + static_cast<size_t>(y) * w1 * n;
    for (int x = 0; x < pairs_x; ++x, a += 2 * n, b += 2 * n, d += n) {
      for (int c = 0; c < n; ++c) {
        d[c] = static_cast<Dst>(a[c] + a[n + c] + b[c] + b[n + c]);
      }
    }
  }
  // What is left over (an odd last column or row, or a side of 1) joins the
  // last output column or row.
  for (int y = 0; y < h0; ++y) {
    const int py = std::min(y >> 1, h1 - 1);
    const int first_x = y < 2 * pairs_y ? 2 * pairs_x : 0;
    const Src* s = src + y * src_row + static_cast<size_t>(first_x) * n;
    Dst* row = dst + static_cast<size_t>(py) * w1 * n;
    for (int x = first_x; x < w0; ++x, s += n) {
      Dst* d = row + static_cast<size_t>(std::min(x >> 1, w1 - 1)) * n;
      for (int c = 0; c < n; ++c) d[c] = static_cast<Dst>(d[c] + s[c]);
    }
  }
}

template <typename Src, typename Dst>
void SumLevel(const Src* src, int w0, int h0, int channels, int w1, int h1,
              Dst* dst) {
  if (channels == 9) {
    SumLevelImpl<9>(src, w0, h0, channels, w1, h1, dst);
  } else if (channels == 64) {
    SumLevelImpl<64>(src, w0, h0, channels, w1, h1, dst);
  } else {
    SumLevelImpl<0>(src, w0, h0, channels, w1, h1, dst);
  }
}

// SumLevel from a base of one bit per count (one word per texel): the rows
// of each output row are unpacked to bytes, then summed as a strip of one
// output row.
template <typename Dst>
void SumBitLevel(const uint64_t* words, int w0, int h0, int channels, int w1,
                 int h1, Dst* dst) {
  const size_t row_values = static_cast<size_t>(w0) * channels;
  std::vector<uint8_t> strip(3 * row_values);
  for (int py = 0; py < h1; ++py) {
    // ROUND_DOWN: rows 2 py, 2 py + 1, and the odd last row for the last.
    const int y0 = std::min(2 * py, h0 - 1);
    const int y1 = py == h1 - 1 ? h0 : 2 * py + 2;
    uint8_t* out = strip.data();
    for (int y = y0; y < y1; ++y) {
      const uint64_t* row = words + static_cast<size_t>(y) * w0;
      for (int x = 0; x < w0; ++x, out += channels) {
        for (int c = 0; c < channels; ++c) {
          out[c] = static_cast<uint8_t>((row[x] >> c) & 1u);
        }
      }
    }
    SumLevel(strip.data(), w0, y1 - y0, channels, w1, 1,
             dst + static_cast<size_t>(py) * w1 * channels);
  }
}

// out[c] = the counts of `texel` in interleaved `values`; kFixed as in
// SumLevelImpl (a constant count lets the compiler convert whole vectors).
template <int kFixed, typename T>
void CopyCountsImpl(const T* v, int channels, double* out) {
  const int n = kFixed > 0 ? kFixed : channels;
  for (int c = 0; c < n; ++c) out[c] = static_cast<double>(v[c]);
}

template <typename T>
void CopyCounts(const std::vector<T>& values, size_t texel, int channels,
                double* out) {
  const T* v = values.data() + texel * channels;
  if (channels == 9) {
    CopyCountsImpl<9>(v, channels, out);
  } else if (channels == 64) {
    CopyCountsImpl<64>(v, channels, out);
  } else {
    CopyCountsImpl<0>(v, channels, out);
  }
}

}  // namespace

CountPyramid::CountPyramid(int width, int height, int channels,
                           std::vector<uint8_t> base)
    : channels_(channels), width_(width), height_(height) {
  CheckBase(base.size(), static_cast<size_t>(width) * height * channels);
  const uint64_t max_base =
      base.empty() ? 0 : *std::max_element(base.begin(), base.end());
  levels_.emplace_back(std::move(base));
  BuildLevels(max_base);
}

CountPyramid::CountPyramid(int width, int height, int channels,
                           std::vector<uint64_t> bits)
    : channels_(channels), width_(width), height_(height) {
  if (channels > 64) {
    throw std::invalid_argument("CountPyramid: " + std::to_string(channels) +
                                " channels do not fit a 64-bit word");
  }
  CheckBase(bits.size(), static_cast<size_t>(width) * height);
  uint64_t any = 0;
  for (uint64_t word : bits) any |= word;
  levels_.emplace_back(BaseBits{std::move(bits)});
  BuildLevels(any != 0 ? 1 : 0);
}

void CountPyramid::CheckBase(size_t values, size_t expected) const {
  if (width_ < 1 || height_ < 1 || channels_ < 1 || values != expected) {
    throw std::invalid_argument(
        "CountPyramid: inconsistent base of " + std::to_string(values) +
        " values for " + std::to_string(width_) + " x " +
        std::to_string(height_) + " x " + std::to_string(channels_));
  }
}

void CountPyramid::BuildLevels(uint64_t max_base) {
  const int levels = MipLevelCount(width_, height_);
  levels_.reserve(levels);
  for (int level = 1; level < levels; ++level) {
    const int w1 = MipLevelSize(width_, level),
              h1 = MipLevelSize(height_, level);
    // The largest count of the level: the base's largest value times the
    // texels of its largest block, the last one (it takes the odd rest).
    const uint64_t bound =
        max_base * static_cast<uint64_t>(Texels(level, w1 - 1, h1 - 1));
    if (bound > UINT32_MAX) {
      throw std::invalid_argument("CountPyramid: level " +
                                  std::to_string(level) +
                                  " counts could exceed 32 bits");
    }
    const size_t size = static_cast<size_t>(w1) * h1 * channels_;
    LevelData next;
    if (bound <= UINT8_MAX) {
      next = std::vector<uint8_t>(size, 0);
    } else if (bound <= UINT16_MAX) {
      next = std::vector<uint16_t>(size, 0);
    } else {
      next = std::vector<uint32_t>(size, 0);
    }
    const int w0 = MipLevelSize(width_, level - 1),
              h0 = MipLevelSize(height_, level - 1);
    std::visit(
        [&](const auto& src, auto& dst) {
          if constexpr (std::is_same_v<std::decay_t<decltype(dst)>, BaseBits>) {
            throw std::logic_error("CountPyramid: bits above the base");
          } else if constexpr (std::is_same_v<std::decay_t<decltype(src)>,
                                              BaseBits>) {
            SumBitLevel(src.words.data(), w0, h0, channels_, w1, h1,
                        dst.data());
          } else {
            SumLevel(src.data(), w0, h0, channels_, w1, h1, dst.data());
          }
        },
        levels_.back(), next);
    levels_.push_back(std::move(next));
  }
}

int CountPyramid::width(int level) const { return MipLevelSize(width_, level); }
int CountPyramid::height(int level) const {
  return MipLevelSize(height_, level);
}

void CountPyramid::Counts(int level, int x, int y, double* out) const {
  // A switch rather than std::visit: the evaluations fetch a texel each,
  // and the visit's indirect call cost Algorithm 3.1 a third of its speed.
  const size_t texel = static_cast<size_t>(y) * width(level) + x;
  const LevelData& data = levels_[level];
  switch (data.index()) {
    case 0: {
      const uint64_t word = std::get_if<BaseBits>(&data)->words[texel];
      for (int c = 0; c < channels_; ++c) out[c] = (word >> c) & 1u;
      return;
    }
    case 1:
      return CopyCounts(*std::get_if<1>(&data), texel, channels_, out);
    case 2:
      return CopyCounts(*std::get_if<2>(&data), texel, channels_, out);
    default:
      return CopyCounts(*std::get_if<3>(&data), texel, channels_, out);
  }
}

void CountPyramid::RowCounts(int level, int y, float* const* rows) const {
  const int w = width(level);
  const size_t first = static_cast<size_t>(y) * w;
  std::visit(
      [&](const auto& data) {
        if constexpr (std::is_same_v<std::decay_t<decltype(data)>, BaseBits>) {
          const uint64_t* words = data.words.data() + first;
          for (int x = 0; x < w; ++x) {
            for (int c = 0; c < channels_; ++c) {
              rows[c][x] = static_cast<float>((words[x] >> c) & 1u);
            }
          }
        } else {
          const auto* values = data.data() + first * channels_;
          for (int x = 0; x < w; ++x, values += channels_) {
            for (int c = 0; c < channels_; ++c) {
              rows[c][x] = static_cast<float>(values[c]);
            }
          }
        }
      },
      levels_[level]);
}

int CountPyramid::BitsPerCount(int level) const {
  return std::visit(
      [](const auto& data) {
        if constexpr (std::is_same_v<std::decay_t<decltype(data)>, BaseBits>) {
          return 1;
        } else {
          return static_cast<int>(8 * sizeof(*data.data()));
        }
      },
      levels_[level]);
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
