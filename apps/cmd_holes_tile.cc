// clothfit holes tile: a holes parameter file with its mask's tile (the
// counts of the level the model evaluates, io/params_json.h "tile"), so
// that a renderer (api/material.h, which reads no image) and every command
// use the file without the mask.
#include <cstdio>
#include <filesystem>
#include <string>

#include "apps/holes_options.h"
#include "io/params_json.h"

namespace clothfit {

int RunHolesTile(int argc, char** argv) {
  CommandArgs args(
      "holes tile",
      "clothfit holes tile --params P.json [--mask M.png] [--method M] "
      "[--level L] --out Q.json",
      "Analyses the mask of a holes parameter file (--mask, else the file's "
      "own, relative to its folder) and\nwrites the file with the tile of "
      "that level (the 1 x 1 top level by default) and method (the file's,\n"
      "else the extension), at most 4,096 texels. Renderers load the result "
      "without the mask.");
  args.Option("params", "P.json", "a holes parameter file");
  AddMaskOptions(&args);
  args.Option("method", "M", "alg31 or extension (default: the file's)");
  args.Option("level", "L", "pyramid level: top (1 x 1) or 0..", "top");
  args.Option("out", "Q.json", "the parameter file with its tile");
  if (!args.Parse(argc, argv, 3)) return 0;
  const std::string params = args.Required("params");
  const std::string out = args.Required("out");
  ParamFile file = ReadParamFile(params);
  HolesModel model = ModelOf<HolesModel>(file, params);
  std::string mask_path = args.Has("mask") ? args.Get("mask") : "";
  if (mask_path.empty()) {
    if (file.holes.path.empty()) {
      args.Fail(params + " names no mask: give --mask M.png");
    }
    mask_path = (std::filesystem::path(params).parent_path() / file.holes.path)
                    .string();  // relative to the file's folder
  } else {
    file.holes.path = mask_path;
    file.holes.threshold = args.GetDouble("threshold");
  }
  if (args.Has("method")) file.holes.method = MethodOption(args);
  const HoleMethod method = file.holes.method.value_or(HoleMethod::kExtension);
  const Mask mask = LoadMask(args, mask_path);
  const HoleTexture texture =
      AnalyzeMask(mask, method == HoleMethod::kExtension);
  const int level = LevelOption(args, texture);
  const HolesTile tile = HolesTileOf(texture, method, level);
  model.tile = StorableTile(tile);
  if (!model.tile) {
    args.Fail("level " + std::to_string(level) + " has " +
              std::to_string(tile.texels.counts.size()) +
              " texels; a file holds at most " +
              std::to_string(kMaxStoredTileTexels) +
              " (choose a higher level)");
  }
  file.params = model;
  WriteParamFile(file, out);
  std::printf("mask %s: %d x %d texels, level %d (%zu texels), %s\nwrote %s\n",
              mask_path.c_str(), mask.width, mask.height, level,
              tile.texels.counts.size(), HoleMethodName(method), out.c_str());
  return 0;
}

}  // namespace clothfit
