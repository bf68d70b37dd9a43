// Mip levels as OpenEXR's MIPMAP_LEVELS with ROUND_DOWN, the layout of
// every pyramid of clothfit (parameter mip maps, Lafortune group fits,
// hole count pyramids): level l of a W x H base has max(1, W >> l) x
// max(1, H >> l) texels, down to 1 x 1; an odd last row or column joins
// the group before it.
#pragma once

#include <algorithm>

namespace clothfit {

// The size of level `level` along a side of `base` texels.
inline int MipLevelSize(int base, int level) {
  return std::max(1, base >> level);
}

// The texel of the next level that texel x of a level joins, along a side
// of `next_size` texels there: x / 2, an odd last texel joining the group
// before it (ROUND_DOWN).
inline int MipParent(int x, int next_size) {
  return std::min(x / 2, next_size - 1);
}

// The number of levels of a width x height base (down to 1 x 1).
inline int MipLevelCount(int width, int height) {
  int levels = 1;
  for (int side = std::max(width, height); side > 1; side >>= 1) ++levels;
  return levels;
}

}  // namespace clothfit
