// clothfit fit --model slab: tau and albedo of the optically thin slab
// (docs/models.md) from one or more tables, with the validity report.
#include <iostream>

#include "apps/commands.h"
#include "fitting/slab_fit.h"
#include "io/atomic_file.h"
#include "io/input_error.h"

namespace clothfit {

int RunFitSlab(const CommandArgs& args, const SolverOptions& solver) {
  for (const char* option :
       {"preset", "generic-start", "tolerance", "fit-scale"}) {
    if (args.Has(option)) {
      args.Fail(std::string("--") + option + " is not available for slab fits");
    }
  }
  args.Required("data");
  const std::vector<std::string> paths = ListOption(args, "data");
  // Each table of the list is an input (Files checks --data as one name).
  for (const std::string& path : paths) {
    CheckOutputsDistinct({{"--out", args.Get("out")}}, {{"--data", path}});
  }
  if (paths.empty()) args.Fail("option '--data': needs a table");
  std::vector<MeasurementTable> tables;
  for (const std::string& path : paths) {
    tables.push_back(ReadTableOption(args, path));
  }

  SlabFitOptions options;
  options.solver = solver;
  options.per_channel_tau = args.Has("per-channel-tau");
  options.fix = ListOption(args, "fix");
  options.free_only = ListOption(args, "free");
  if (args.Has("starts")) {
    const long n = args.GetInt("starts");
    if (n < 1 || n > 100) args.Fail("option '--starts': must be in [1, 100]");
    options.solve_starts = static_cast<int>(n);
  }
  if (args.Has("init")) {
    const ParamFile init = ReadParamFile(args.Get("init"));
    if (!std::holds_alternative<SlabParams>(init.params)) {
      args.Fail(args.Get("init") + ": expected a slab parameter file");
    }
    options.init = std::get<SlabParams>(init.params);
  }
  SlabFitResult result;
  try {
    result = FitSlab(tables, options);
  } catch (const InputError& e) {  // name the tables
    throw InputError(args.Get("data") + ": " + e.what());
  }

  std::vector<double> truth;
  if (args.Has("truth")) {
    const ParamFile file = ReadParamFile(args.Get("truth"));
    if (const auto* p = std::get_if<SlabParams>(&file.params)) {
      truth = SlabValuesInReportOrder(*p, result.report);
    }
  }
  FitExtras extras;
  if (result.report.usable) {
    extras.text = SlabValidityText(result.validity) + "\n";
    extras.json.emplace_back("validity", SlabValidityJson(result.validity));
  }
  const int status =
      FinishFit(args, result.params, result.report, truth, extras);
  if (result.report.usable && !result.validity.within_regime) {
    std::cerr << "warning: the data are outside the slab model's regime "
                 "(see 'validity' above and docs/slab.md)\n";
  }
  return status;
}

}  // namespace clothfit
