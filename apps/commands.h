// The clothfit subcommands. Each returns the process exit status: 0 success,
// 1 a fit without a usable solution, 2 bad input or usage (they throw
// InputError for that; main() prints it and returns 2).
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <utility>
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
int RunMerge(int argc, char** argv);         // merge: parts of a texel map
int RunBlocks(int argc, char** argv);        // blocks: the parts' regions
int RunExport(int argc, char** argv);        // export --format gltf
int RunFitHoles(int argc, char** argv);      // fit --model holes
int RunHoles(int argc, char** argv);         // holes analyze|eval|truth
int RunPlot(int argc, char** argv);
int RunRender(int argc, char** argv);
int RunReport(int argc, char** argv);
int RunSynthSlab(int argc, char** argv);  // synth --model slab
int RunPreset(int argc, char** argv);
int RunPresets(int argc, char** argv);
int RunSynth(int argc, char** argv);

// plot and report (apps/cmd_plot.cc; clothfit-full only): the model
// options (--params, --preset) and the polar panels' (--incidence-deg,
// --phi-deg, --window-deg); PlotLabel names the model and --data for
// titles; PrintNotes prints WriteFitFigures' notes on stderr.
struct PlotOptions;
void AddPlotOptions(CommandArgs* args);
PlotOptions ReadPlotOptions(const CommandArgs& args);
std::string PlotLabel(const CommandArgs& args);
void PrintNotes(const std::vector<std::string>& notes);
// The table of --data (if given; not transmittance) into *table, and the
// model of --params / --preset, evaluable as the table's quantity (the
// BRDF without a table).
ParamFile LoadPlotInputs(const CommandArgs& args,
                         std::optional<MeasurementTable>* table);

// --quantity value: "brdf" | "cosine_weighted" (models predict no
// transmittance).
Quantity ModelQuantityOption(const CommandArgs& args, const std::string& name);

// The parameters named by --FILE_OPTION FILE (e.g. --params) or --preset
// NAME; exactly one of the two must be given.
// The preset `name`; an unknown name fails naming the closest preset.
ClothParams RequirePreset(const CommandArgs& args, const std::string& name);
ParamFile LoadModelOption(const CommandArgs& args,
                          const std::string& file_option = "params");

// LoadModelOption(args) for a command that evaluates the model as
// `quantity`: a holes file gets its mask (holes/hole_texture.h
// LoadHolesModel); a model that does not predict `quantity` fails naming
// `source` (the table or option it comes from).
ParamFile LoadEvaluableModel(const CommandArgs& args, Quantity quantity,
                             const std::string& source);

// The value of option `name` split at commas (--fix, --free, lists of
// files and numbers): {} when the option is absent and has no default; an
// empty item ("a,,b", "a,", ",a") fails with the option's name.
std::vector<std::string> ListOption(const CommandArgs& args,
                                    const std::string& name);
// The value of option `name` as comma-separated finite numbers (at least
// one); a bad item fails with the option's name.
std::vector<double> NumberListOption(const CommandArgs& args,
                                     const std::string& name);

// The value of --model M / --model=M in argv[first..], "" when absent (for
// commands that dispatch on it before parsing their options).
std::string ModelArgument(int argc, char** argv, int first = 2);

// docs/models.md: where the slab's single-scattering form is not accurate, the
// tool says so. When `p` lies outside the model's regime (the estimated
// error SlabParamsSingleScatterError above kSlabRegimeTolerance, the rule of
// fit --model slab's validity report), prints one line on stderr starting
// "note: " that names tau, the albedo and what to use instead (synth --mc).
// Direct transmittance is exact and needs no note.
void NoteSlabRegime(const SlabParams& p);

// The solver options of a fit command (fitting/fit_result.h SolverOptions,
// the same ranges for every fit): --max-iterations, --threads (what runs
// on them: `threads_help`), --linear-solver, and with `robust_loss`
// --loss and --loss-scale; `defaults` are the command's. Reading them
// adds a progress line on a terminal.
// noise_default: what --noise is without it, in words.
void AddSolverOptions(CommandArgs* args, const SolverOptions& defaults,
                      bool robust_loss, const std::string& threads_help,
                      const std::string& noise_default =
                          "table with a sigma column, else "
                          "relative");
SolverOptions ReadSolverOptions(const CommandArgs& args, bool robust_loss);

// Reads the table at `path`, dropping invalid rows (with a warning naming
// the first) when the command has --skip-invalid and it is given, and
// prints the reader's warnings (radians read as degrees, percent).
MeasurementTable ReadTableOption(const CommandArgs& args,
                                 const std::string& path,
                                 ReadTableOptions read_options = {});
// WriteTable with a progress line ("writing PATH") on a terminal.
void WriteTableWithProgress(const MeasurementTable& table,
                            const std::string& path);
// A warning when `table`'s metadata says its values are on an arbitrary
// scale and --fit-scale is not given.
void WarnArbitraryScale(const CommandArgs& args, const MeasurementTable& table);
// The table of --data, with --skip-invalid (a warning says how many rows
// were dropped).
MeasurementTable ReadDataOption(const CommandArgs& args);
// A warning on stderr when a reflection-only model's fit left table rows
// out (report.rows_not_used).
void WarnNotReflection(const FitReport& report, const std::string& model);

// The end of a fit command: prints `preface` and the report's summary
// (with `truth`, may be empty), and when the fit is usable calls `write`
// with the "fit" object (JSON text) and says so; warns about parameters the
// data cannot determine. Returns 0, or 1 when the fit is unusable (nothing
// written) or did not converge.
// identifiability_hint follows report.identifiability in the warning: what
// to do about it ("" where the message says so itself).
inline constexpr char kFixHint[] =
    " (the data do not determine them; fix them with --fix)";
int FinishFit(const FitReport& report, const std::vector<double>& truth,
              const std::string& out_path,
              const std::function<void(const std::string&)>& write,
              const std::string& preface = "",
              const std::string& identifiability_hint = kFixHint);

// What a fit adds besides its FitReport: text printed before the summary,
// and (key, JSON text) entries added to the "fit" object.
struct FitExtras {
  std::string text;
  std::vector<std::pair<std::string, std::string>> json;
};

// FinishFit for a parameter file: writes `fitted` to --out with the "fit"
// object and the extras' entries.
int FinishFit(const CommandArgs& args, const ModelParams& fitted,
              const FitReport& report, const std::vector<double>& truth,
              const FitExtras& extras);

// fit --model slab, after RunFit parsed the options (apps/cmd_fit_slab.cc).
int RunFitSlab(const CommandArgs& args, const SolverOptions& solver);

// fit --model auto, after RunFit parsed the options (apps/cmd_fit_auto.cc).
int RunFitAuto(const CommandArgs& args, const SolverOptions& solver);

}  // namespace clothfit
