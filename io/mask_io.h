// Binary masks of opaque and transparent texels (docs/models.md), read from any
// image OpenImageIO reads (PNG, TIFF, EXR, JPEG, ...).
//
// Which channel: the alpha channel when the image has one (opaque where
// alpha >= threshold), else the luminance 0.2126 R + 0.7152 G + 0.0722 B
// of the stored values (no colour-space conversion; a one-channel image is
// its own luminance), where bright texels are holes (transparent where
// luminance >= threshold, as a backlit photograph shows them; the thesis's
// Fig. 4.2 draws holes white). `invert` swaps opaque and transparent.
// Integer formats are read as value / max (8-bit 255 -> 1).
//
// Texel (x, y) is column x, row y of the image (row 0 first in the file).
// Any size is accepted (not only powers of two); the mask tiles the plane,
// so the neighbour of the last column is the first (see docs/holes.md).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace clothfit {

struct Mask {
  int width = 0, height = 0;
  // opaque[y * width + x]: 1 opaque, 0 transparent.
  std::vector<uint8_t> opaque;

  // Texel (x, y) with the tiling applied (any integers).
  bool Opaque(int64_t x, int64_t y) const {
    x %= width;
    y %= height;
    if (x < 0) x += width;
    if (y < 0) y += height;
    return opaque[static_cast<size_t>(y) * width + x] != 0;
  }
  // Fraction of opaque texels.
  double OpaqueFraction() const;
};

enum class MaskSource { kAuto, kAlpha, kLuminance };

struct MaskReadOptions {
  double threshold = 0.5;  // in (0, 1]
  MaskSource source = MaskSource::kAuto;
  bool invert = false;
};

// Largest mask accepted (texels), against corrupt headers and overflow of
// the count pyramid (counts up to 2 width height fit in 32 bits).
inline constexpr int64_t kMaxMaskTexels = int64_t{1} << 28;

// Throws InputError naming the file and the problem (missing, unreadable,
// empty or too large image, alpha requested but absent, bad threshold).
Mask ReadMask(const std::string& path, const MaskReadOptions& options = {});

// Writes an 8-bit grey PNG (opaque black, holes white; the format follows
// from the extension: .png, .tif, .bmp, ...) atomically. Throws InputError.
void WriteMask(const Mask& mask, const std::string& path);

// A mask from rows of text, '#' opaque and '.' transparent (tests, docs):
// MaskFromRows({"#.#", "..."}). Throws InputError on ragged rows.
Mask MaskFromRows(const std::vector<std::string>& rows);

// "mask.png" style: "alpha", "luminance" or "auto".
const char* MaskSourceName(MaskSource source);

}  // namespace clothfit
