#include <string>

#include "apps/commands.h"
#include "models/presets.h"

namespace clothfit {

Quantity ModelQuantityOption(const CommandArgs& args, const std::string& name) {
  const std::string text = args.Get(name);
  const std::optional<Quantity> q = ParseQuantity(text);
  if (!q || *q == Quantity::kTransmittance) {
    args.Fail("option '--" + name + "': expected brdf or cosine_weighted, got '" +
              text + "'");
  }
  return *q;
}

ParamFile LoadModelOption(const CommandArgs& args) {
  if (args.Has("params") == args.Has("preset")) {
    args.Fail("give exactly one of --params FILE and --preset NAME");
  }
  if (args.Has("params")) return ReadParamFile(args.Get("params"));
  ClothParams cloth;
  if (!GetPreset(args.Get("preset"), &cloth)) {
    args.Fail("unknown preset '" + args.Get("preset") +
              "'; 'clothfit presets' lists them");
  }
  return ParamFile{cloth, ""};
}

}  // namespace clothfit
