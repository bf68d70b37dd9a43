// What the image-stack reader (io/image_stack.cc) and writer
// (io/image_write.cc) share. Not installed.
#pragma once

#include <cstdint>
#include <string>

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

}  // namespace image_stack_internal
}  // namespace clothfit
