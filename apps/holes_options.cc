#include "apps/holes_options.h"

#include <optional>
#include <string>

namespace clothfit {

void AddMaskOptions(CommandArgs* args) {
  args->Option("mask", "M.png",
               "mask image: alpha >= T is opaque, else luminance < T");
  args->Option("threshold", "T", "mask threshold, (0, 1]", "0.5");
  args->Option("source", "S", "mask channel: auto, alpha or luminance", "auto");
  args->Flag("invert", "swap the mask's opaque and transparent texels");
}

Mask LoadMask(const CommandArgs& args, const std::string& path) {
  MaskReadOptions options;
  options.threshold = args.GetDouble("threshold");
  if (!(options.threshold > 0.0 && options.threshold <= 1.0)) {
    args.Fail("option '--threshold': must be in (0, 1]");
  }
  const std::string source = args.Get("source");
  if (source == "alpha") {
    options.source = MaskSource::kAlpha;
  } else if (source == "luminance") {
    options.source = MaskSource::kLuminance;
  } else if (source != "auto") {
    args.Fail("option '--source': expected auto, alpha or luminance, got '" +
              source + "'");
  }
  options.invert = args.Has("invert");
  return ReadMask(path, options);
}

Mask LoadMask(const CommandArgs& args) {
  return LoadMask(args, args.Required("mask"));
}

// How the ratios are computed (eval, fit).
void AddMethodOptions(CommandArgs* args) {
  args->Option("method", "M", "alg31 or extension", "extension");
  args->Option("level", "L",
               "pyramid level evaluated and averaged over the tile: top (1 x "
               "1) or 0..",
               "top");
}

HoleMethod MethodOption(const CommandArgs& args) {
  const std::optional<HoleMethod> method = ParseHoleMethod(args.Get("method"));
  if (!method) {
    args.Fail("option '--method': expected alg31 or extension, got '" +
              args.Get("method") + "'");
  }
  return *method;
}

// --level: "top" (-1) or 0..top.
int LevelOption(const CommandArgs& args, const HoleTexture& texture) {
  if (args.Get("level") == "top") return texture.counts.levels() - 1;
  const long level = args.GetInt("level");
  if (level < 0 || level >= texture.counts.levels()) {
    args.Fail("option '--level': the mask's pyramid has levels 0.." +
              std::to_string(texture.counts.levels() - 1) + " (or top)");
  }
  return static_cast<int>(level);
}

std::shared_ptr<const HolesTile> StorableTile(const HolesTile& tile) {
  if (tile.texels.counts.size() > kMaxStoredTileTexels) return nullptr;
  return std::make_shared<const HolesTile>(tile);
}

}  // namespace clothfit
