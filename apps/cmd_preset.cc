// clothfit preset NAME / clothfit presets (docs/cli.md).
#include <iostream>

#include "apps/commands.h"
#include "models/presets.h"

namespace clothfit {

int RunPreset(int argc, char** argv) {
  CommandArgs args("preset", "clothfit preset NAME [--out P.json]",
                   "Prints (or writes) the parameter file of a preset fabric "
                   "of Sadeghi et al. 2013 (Tables 2 and 3).");
  args.Option("out", "P.json", "write to this file instead of stdout");
  args.Positionals(1);
  if (!args.Parse(argc, argv, 2)) return 0;
  if (args.Positional().size() != 1) {
    args.Fail("expected one preset name (see 'clothfit presets')");
  }
  const ClothParams cloth = RequirePreset(args, args.Positional()[0]);
  const ParamFile file{cloth, ""};
  if (args.Has("out")) {
    WriteParamFile(file, args.Get("out"));
  } else {
    std::cout << FormatParamFile(file);
  }
  return 0;
}

int RunPresets(int argc, char** argv) {
  CommandArgs args("presets", "clothfit presets",
                   "Lists the preset fabrics, one name per line.");
  if (!args.Parse(argc, argv, 2)) return 0;
  for (const std::string& name : PresetNames()) std::cout << name << "\n";
  return 0;
}

}  // namespace clothfit
