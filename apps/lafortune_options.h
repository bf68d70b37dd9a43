// The options of clothfit fit --model lafortune and the end of a texel-map
// fit: fit parses them, merge parses the fit options its parts record
// with the same declarations (docs/scale.md).
#pragma once

#include <optional>
#include <string>

#include "apps/cli_args.h"
#include "fitting/lafortune_mip.h"
#include "io/param_mipmap.h"

namespace clothfit {

// What the options ask of a Lafortune fit. options.fit.start points at
// init: keep the object where it was filled.
struct LafortuneFitSetup {
  LafortuneFitSetup() = default;
  LafortuneFitSetup(const LafortuneFitSetup&) = delete;
  LafortuneFitSetup& operator=(const LafortuneFitSetup&) = delete;
  LafortuneMipOptions options;
  std::optional<LafortuneModel> init;
  bool select = false;  // --select heldout
  long folds = 5;
};

// The parser of fit --model lafortune, every option declared.
CommandArgs LafortuneFitArgs();
// The fit's options from parsed arguments (--init read); bad values fail
// naming the option.
void ReadLafortuneFitOptions(const CommandArgs& args, LafortuneFitSetup* setup);

// The end of a texel-map fit: prints what the fits came to per level,
// writes `map` to out_path (and its index), warns about texels at a cap,
// search limit or scaled, and returns the exit status (1 for texels
// without a usable fit, at a search limit or scaled).
int FinishLafortuneMip(const LafortuneMipResult& result, const ParamMipmap& map,
                       const std::string& out_path);

}  // namespace clothfit
