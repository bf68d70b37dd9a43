// A holes model's tile (models/holes_tile.h) in its parameter file, the
// "tile" object (io/params_json.h):
//   {"area": A, "texels": [T_0, ...], "counts": [[9 counts], ...],
//    "distances": [[64 cumulative run counts], ...]}
// one entry per texel of the level the fit used (the 1 x 1 top level by
// default), counts in models/holes.h order, run counts in
// models/holes_distance.h order; "distances" only for the extension.
// Internal to clothfit_io.
#pragma once

#include <string>

#include "io/json_object_reader_internal.h"
#include "models/holes_tile.h"

namespace clothfit {
namespace io_internal {

// The tile of object `tile` (at key path "tile" of `file`), evaluated with
// `method`. Throws InputError naming the key (a wrong shape, more than
// kMaxStoredTileTexels texels, or a tile ValidateHolesTile refuses).
HolesTile ReadHolesTile(const json& tile, const std::string& file,
                        HoleMethod method);

json FormatHolesTile(const HolesTile& tile);

}  // namespace io_internal
}  // namespace clothfit
