// The clothfit subcommands. Each returns the process exit status: 0 success,
// 1 a fit without a usable solution, 2 bad input or usage (they throw
// InputError for that; main() prints it and returns 2).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "apps/cli_args.h"
#include "fitting/fit_result.h"
#include "io/params_json.h"
#include "io/table.h"

namespace clothfit {

int RunBench(int argc, char** argv);
int RunEval(int argc, char** argv);
int RunFit(int argc, char** argv);
int RunFitLafortune(int argc, char** argv);  // fit --model lafortune
int RunFitHoles(int argc, char** argv);      // fit --model holes
int RunHoles(int argc, char** argv);         // holes analyze|eval|truth
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

// "a,b,,c" -> {"a", "b", "c"} (--fix, --free).
std::vector<std::string> SplitList(const std::string& text);

// The solver options of a fit command: --loss, --loss-scale,
// --max-iterations and --threads (apps/cmd_fit.cc), and their values (with
// a progress line on a terminal).
void AddSolverOptions(CommandArgs* args);
SolverOptions ReadSolverOptions(const CommandArgs& args);

// The table of --data, with --skip-invalid (a warning says how many rows
// were dropped).
MeasurementTable ReadDataOption(const CommandArgs& args);

// The end of a fit command: prints `preface` and the report's summary
// (with `truth`, may be empty), and when the fit is usable calls `write`
// with the "fit" object (JSON text) and says so; warns about parameters the
// data cannot determine. Returns 0, or 1 when the fit is unusable (nothing
// written) or did not converge.
int FinishFit(const FitReport& report, const std::vector<double>& truth,
              const std::string& out_path,
              const std::function<void(const std::string&)>& write,
              const std::string& preface = "");

}  // namespace clothfit
