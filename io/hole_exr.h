// The count pyramids of a hole texture as tiled, mip-mapped OpenEXR files
// with a JSON index (through io/param_mipmap.h): the nine counts of
// Algorithm 3.1 (channels "walls.top" ... "opaques", models/holes.h) in
// one file, the cumulative run counts of the extension ("distance.E.0" ...
// "distance.SE.7", models/holes_distance.h) in another. Every level of the
// pyramid is one MIPMAP_LEVELS / ROUND_DOWN level of the file; the values
// are the integer counts as FLOAT (exact up to 2^24 = 16.7 million).
#pragma once

#include <string>
#include <vector>

#include "io/count_pyramid.h"

namespace clothfit {

enum class CountKind { kHoleCounts, kHoleDistances };

// Channel names of a kind, in channel order.
std::vector<std::string> CountChannelNames(CountKind kind);

// Writes `path` and `path`.json (index; `metadata_json` is a JSON object
// stored in it, with "kind" added). Throws InputError.
void WriteCountPyramid(const CountPyramid& pyramid, CountKind kind,
                       const std::string& metadata_json,
                       const std::string& path);

// Reads a file written by WriteCountPyramid back. The level-0 values must
// be non-negative integers small enough for level 0 (<= 2); the pyramid is
// rebuilt from them and every stored level is checked against the sums.
// Throws InputError naming the file and the problem (wrong kind or
// channels, non-integer count, a level that is not the sum of the one
// below). *metadata_json (may be null) receives the index's metadata.
CountPyramid ReadCountPyramid(const std::string& path, CountKind kind,
                              std::string* metadata_json = nullptr);

}  // namespace clothfit
