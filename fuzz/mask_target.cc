// Fuzz target: masks (io/mask_io.h), read through OpenImageIO from a
// temporary file.
#include <cstdio>
#include <cstring>
#include <string>

#include "fuzz/fuzz_util.h"
#include "io/input_error.h"
#include "io/mask_io.h"

namespace clothfit {
namespace {

using fuzz::Require;

// The extension of the format the file's first bytes announce (OpenImageIO
// picks its reader by extension first), ".png" when none.
const char* ExtensionFor(const uint8_t* data, size_t size) {
  auto starts = [&](const char* magic, size_t n) {
    return size >= n && std::memcmp(data, magic, n) == 0;
  };
  if (starts("\x76\x2f\x31\x01", 4)) return ".exr";
  if (starts("II*\0", 4) || starts("MM\0*", 4)) return ".tif";
  if (starts("BM", 2)) return ".bmp";
  if (starts("\xff\xd8\xff", 3)) return ".jpg";
  if (starts("P", 1)) return ".pnm";
  return ".png";
}

void CheckMask(const Mask& mask) {
  Require(mask.width >= 1 && mask.height >= 1, "a mask has texels");
  Require(int64_t{mask.width} * mask.height <= kMaxMaskTexels,
          "no larger than kMaxMaskTexels");
  Require(mask.opaque.size() == static_cast<size_t>(mask.width) * mask.height,
          "one entry per texel");
  for (const uint8_t v : mask.opaque) Require(v == 0 || v == 1, "0 or 1");
}

}  // namespace

void FuzzMask(const uint8_t* data, size_t size) {
  const std::string path =
      fuzz::ScratchDir() + "/mask" + ExtensionFor(data, size);
  fuzz::WriteBytes(path, data, size);
  MaskReadOptions luminance;
  luminance.source = MaskSource::kLuminance;
  luminance.invert = true;
  luminance.threshold = 0.25;
  for (const MaskReadOptions& options : {MaskReadOptions{}, luminance}) {
    try {
      CheckMask(ReadMask(path, options));
    } catch (const InputError&) {
      // the expected answer to bad input
    }
  }
  std::remove(path.c_str());
}

}  // namespace clothfit
