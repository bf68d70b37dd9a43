// Spatially varying parameters as a tiled, mip-mapped OpenEXR file (OpenEXR
// MIPMAP_LEVELS, ROUND_DOWN), one named FLOAT channel per parameter (e.g.
// "lobe0.Cx.R", "lut.12.A"), plus a JSON index beside it naming the
// channels, their meaning and units, and any extra metadata (e.g. the view
// directions of a lookup table). Level l of a W x H base has
// max(1, W >> l) x max(1, H >> l) texels; every level holds every channel.
// A map holds either every level down to 1 x 1 (MIPMAP_LEVELS) or the base
// level alone (a tiled ONE_LEVEL file, for fits without mip levels).
#pragma once

#include <functional>
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

// A map too large to hold as floats at once (the 64 run counts of a
// 4096 x 4096 mask take 5.7 GB), written a band of rows at a time.
struct ParamMipmapBands {
  std::vector<std::string> channels;  // channel names, in order
  int width = 0, height = 0;          // level 0
  bool mipmapped = true;  // every level down to 1 x 1, else level 0 alone
  std::string metadata_json = "{}";
  // Writes every value of rows [y0, y0 + band->height) of `level` into
  // band->data[c][(y - y0) * band->width + x]; width, height and data come
  // sized. Called for the bands of level 0 top to bottom, then level 1 ...
  std::function<void(int level, int y0, ParamImage* band)> fill;
};

// Writes the same files as WriteParamMipmap from `bands`, holding one band
// of 32 rows at a time. A non-finite value fails (InputError naming the
// channel, level and texel) and leaves the files as they were.
void WriteParamMipmapBands(const ParamMipmapBands& bands,
                           const std::string& path);

// Reads both files back. Throws InputError naming the file and the problem
// (missing file, not a mip-mapped EXR, channel missing from the index,
// truncated data).
ParamMipmap ReadParamMipmap(const std::string& path);

}  // namespace clothfit
