// Spatially varying parameters as a tiled, mip-mapped OpenEXR file (OpenEXR
// MIPMAP_LEVELS, ROUND_DOWN), one named FLOAT channel per parameter (e.g.
// "lobe0.Cx.R", "lut.12.A"), plus a JSON index beside it naming the
// channels, their meaning and units, and any extra metadata (e.g. the view
// directions of a lookup table). Level l of a W x H base has
// max(1, W >> l) x max(1, H >> l) texels; every level holds every channel.
// A map holds either every level down to 1 x 1 (MIPMAP_LEVELS) or the base
// level alone (a tiled ONE_LEVEL file, for fits without mip levels).
#pragma once

#include <string>
#include <vector>

namespace clothfit {

struct ParamImage {
  int width = 0, height = 0;
  // data[c][y * width + x] for channel c (same order as channel names).
  std::vector<std::vector<float>> data;
};

struct ParamMipmap {
  std::vector<std::string> channels;  // channel names, in order
  std::vector<ParamImage> levels;     // level 0 first, down to 1 x 1
  // Free-form JSON object (as text) stored in the index under "metadata";
  // "{}" when empty.
  std::string metadata_json = "{}";
};

// Writes `path` (the .exr) and `path` + ".json" (the index), each to a
// temporary name renamed into place when complete. Throws InputError naming
// the path on failure or on an inconsistent mip map (level sizes, channel
// counts, data sizes).
void WriteParamMipmap(const ParamMipmap& mipmap, const std::string& path);

// Reads both files back. Throws InputError naming the file and the problem
// (missing file, not a mip-mapped EXR, channel missing from the index,
// truncated data).
ParamMipmap ReadParamMipmap(const std::string& path);

}  // namespace clothfit
