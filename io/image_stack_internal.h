// What the image-stack reader (io/image_stack.cc, io/stack_image.cc) and
// writer (io/image_write.cc) share. Not installed.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <string>
#include <vector>

#include "io/image_stack.h"
#include "io/input_error.h"

namespace clothfit {
namespace image_stack_internal {

// Largest image accepted (pixels), against corrupt headers.
inline constexpr int64_t kMaxPixels = int64_t{1} << 28;

// The manifest's metadata key naming the per-texel normal image.
inline constexpr const char* kNormalMapKey = "normal_map";

[[noreturn]] inline void Fail(const std::string& file, int line, int column,
                              const std::string& problem) {
  throw InputError(FormatLocation(file, line, column) + ": " + problem);
}

// Pixels of one image, or of a region of it, as floats.
struct Image {
  int width = 0, height = 0;  // the whole image's
  int channels = 0;
  int alpha = -1;               // alpha channel index, -1 when none
  std::vector<int> colour;      // 1 (grey) or 3 (r, g, b) indices
  PixelRegion region;           // the pixels read
  std::vector<float> pixels;    // channels per pixel of region, row-major
  bool integer_pixels = false;  // stored as integers (read scaled to [0, 1])
};

// The image every other of a stack must match in size; width 0: none.
struct ExpectedSize {
  int width = 0, height = 0;
  std::string image;  // the image that has that size
};

// Reads the pixels of `region` of the image at `path` (a region of width 0:
// the whole image): a tiled file by the tiles the region touches, a
// scanline file by the region's rows (whole rows are decoded). Every
// failure is an InputError naming the image and the manifest line that
// lists it; so is an image not of the expected size, a region that is not
// inside the image and a pixel that is not finite.
Image ReadStackImage(const std::string& path, const std::string& manifest,
                     int line, const PixelRegion& region,
                     const ExpectedSize& expected = {});

// The unit normal of every pixel read of a normal map (row-major over its
// region): (x, y, z) in the surface frame from its three colour channels,
// stored as they are in a float image and as 2 v - 1 (v in [0, 1]) in an
// integer one; alpha is ignored.
std::vector<glm::dvec3> NormalsOf(const Image& image, const std::string& path,
                                  const std::string& manifest, int line);

}  // namespace image_stack_internal
}  // namespace clothfit
