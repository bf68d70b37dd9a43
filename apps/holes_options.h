// Options shared by the holes commands (apps/cmd_holes.cc,
// apps/cmd_holes_tile.cc): the mask, the method and the level.
#pragma once

#include <memory>
#include <string>

#include "apps/cli_args.h"
#include "holes/hole_texture.h"
#include "io/mask_io.h"

namespace clothfit {

// --mask, --threshold, --source, --invert.
void AddMaskOptions(CommandArgs* args);
// The mask of --mask, or of `path`, read with the other mask options.
Mask LoadMask(const CommandArgs& args);
Mask LoadMask(const CommandArgs& args, const std::string& path);

// --method, --level: how the ratios are computed (eval, fit, tile).
void AddMethodOptions(CommandArgs* args);
HoleMethod MethodOption(const CommandArgs& args);
// --level: "top" (the pyramid's last level) or 0..top.
int LevelOption(const CommandArgs& args, const HoleTexture& texture);

// The tile to store in a parameter file (io/params_json.h "tile"): null
// when it has more than kMaxStoredTileTexels texels.
std::shared_ptr<const HolesTile> StorableTile(const HolesTile& tile);

// RunHoles' "tile" subcommand (apps/cmd_holes_tile.cc).
int RunHolesTile(int argc, char** argv);

}  // namespace clothfit
