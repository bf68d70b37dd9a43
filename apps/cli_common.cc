#include <string>

#include "apps/commands.h"
#include "models/presets.h"

namespace clothfit {

Quantity ModelQuantityOption(const CommandArgs& args, const std::string& name) {
  const std::string text = args.Get(name);
  const std::optional<Quantity> q = ParseQuantity(text);
  if (!q || *q == Quantity::kTransmittance) {
    args.Fail("option '--" + name +
              "': expected brdf or cosine_weighted, got '" + text + "'");
  }
  return *q;
}

ParamFile LoadModelOption(const CommandArgs& args,
                          const std::string& file_option) {
  if (args.Has(file_option) == args.Has("preset")) {
    args.Fail("give exactly one of --" + file_option +
              " FILE and --preset NAME");
  }
  if (args.Has(file_option)) return ReadParamFile(args.Get(file_option));
  ClothParams cloth;
  if (!GetPreset(args.Get("preset"), &cloth)) {
    args.Fail("unknown preset '" + args.Get("preset") +
              "'; 'clothfit presets' lists them");
  }
  return ParamFile{cloth, ""};
}

}  // namespace clothfit
