// The clothfit subcommands. Each returns the process exit status: 0 success,
// 1 a fit without a usable solution, 2 bad input or usage (they throw
// InputError for that; main() prints it and returns 2).
#pragma once

#include <string>

#include "apps/cli_args.h"
#include "io/params_json.h"
#include "io/table.h"

namespace clothfit {

int RunBench(int argc, char** argv);
int RunEval(int argc, char** argv);
int RunFit(int argc, char** argv);
int RunFitLafortune(int argc, char** argv);  // fit --model lafortune
int RunPlot(int argc, char** argv);
int RunPreset(int argc, char** argv);
int RunPresets(int argc, char** argv);
int RunSynth(int argc, char** argv);

// --quantity value: "brdf" | "cosine_weighted" (models predict no
// transmittance).
Quantity ModelQuantityOption(const CommandArgs& args, const std::string& name);

// The parameters named by --FILE_OPTION FILE (e.g. --params) or --preset
// NAME; exactly one of the two must be given.
ParamFile LoadModelOption(const CommandArgs& args,
                          const std::string& file_option = "params");

}  // namespace clothfit
