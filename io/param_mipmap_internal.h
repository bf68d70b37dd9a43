// Internals of the parameter mip map files (io/param_mipmap.h) that its
// reader (param_mipmap.cc) and its writers (param_mipmap_write.cc) share.
// Internal to clothfit_io.
#pragma once

#include <ImfFrameBuffer.h>

#include <cstdint>
#include <string>
#include <vector>

#include "io/input_error.h"
#include "io/param_mipmap.h"

namespace clothfit {
namespace param_mipmap_internal {

inline constexpr char kFormat[] = "clothfit-param-mipmap 1";
// The EXR header attribute that holds the index, so that the EXR is
// complete alone; the .exr.json beside it is a copy for people and tools.
inline constexpr char kIndexAttribute[] = "clothfit:index";
// Largest base size accepted (per side).
inline constexpr int64_t kMaxSide = int64_t{1} << 24;

[[noreturn]] inline void Fail(const std::string& path,
                              const std::string& problem) {
  throw InputError(path + ": " + problem);
}

// "" when every value of `image` (rows y0 ... of level `level`) is finite,
// else where the first one that is not lies: "channel 'lobe0.N.R' at level
// 0, texel (3, 4) is NaN".
std::string FirstNonFiniteIn(const std::vector<std::string>& channels,
                             const ParamImage& image, int level, int y0);
// The same over every level.
std::string FirstNonFinite(const ParamMipmap& mipmap);

// A frame buffer with one FLOAT slice per channel over `image`, whose pixel
// (0, 0) sits at (x0, y0) of the file's data window.
Imf::FrameBuffer MakeFrameBuffer(const std::vector<std::string>& channels,
                                 const ParamImage& image, int x0, int y0);

}  // namespace param_mipmap_internal
}  // namespace clothfit
