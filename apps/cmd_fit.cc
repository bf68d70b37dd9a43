// clothfit fit: fits a model's parameters to a measurement table (docs/cli.md).
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <utility>

#include "apps/commands.h"
#include "apps/full_binary.h"
#include "apps/progress.h"
#include "fitting/cloth_fit.h"
#include "fitting/energy.h"
#include "fitting/model_selection.h"
#include "fitting/sheen_fit.h"
#include "fitting/thread_fit.h"
#include "io/atomic_file.h"
#include "io/input_error.h"
#include "io/text_util.h"
#include "models/presets.h"

namespace clothfit {

MeasurementTable ReadTableOption(const CommandArgs& args,
                                 const std::string& path,
                                 ReadTableOptions read_options) {
  read_options.skip_invalid = args.Has("skip-invalid");
  progress::Task task("reading " + path, "MB");
  read_options.progress = [&task](double done, double total) {
    task.Update(done / 1e6, total / 1e6);
  };
  ReadTableResult read = ReadTable(path, read_options);
  if (read.skipped > 0) {
    progress::Warn("skipped " + std::to_string(read.skipped) +
                   " invalid row(s); first: " + read.first_skip_reason);
  }
  for (const std::string& warning : read.warnings) progress::Warn(warning);
  return std::move(read.table);  // not a copy: ~150 bytes a row
}

void WarnArbitraryScale(const CommandArgs& args,
                        const MeasurementTable& table) {
  if (args.Has("fit-scale")) return;
  if (const std::optional<std::string> note = ArbitraryScaleNote(table)) {
    progress::Warn(table.source + ": its metadata says '" +
                   text_util::EscapeControl(*note) +
                   "': a physically based model fits values on an arbitrary "
                   "scale only with --fit-scale (a factor on the model)");
  }
}

MeasurementTable ReadDataOption(const CommandArgs& args) {
  return ReadTableOption(args, args.Required("data"));
}

void WarnNotReflection(const FitReport& report, const std::string& model) {
  if (report.rows_not_used == 0) return;
  std::cerr << "warning: " << report.rows_not_used
            << " row(s) are not reflection (wi.z or wo.z <= 0) and are not "
               "used: the "
            << model << " model is reflection only\n";
}

int FinishFit(const FitReport& report, const std::vector<double>& truth,
              const std::string& out_path,
              const std::function<void(const std::string&)>& write,
              const std::string& preface,
              const std::string& identifiability_hint) {
  progress::FlushWarnings();
  progress::Clear();
  std::cout << preface << FitReportText(report, truth);
  if (!report.usable) {
    std::cerr << "error: the fit did not reach a usable solution: "
              << report.message << "; nothing written\n";
    return 1;
  }
  write(FitReportJson(report));
  std::cout << "wrote " << out_path << "\n";
  if (!report.identifiability.empty()) {
    std::cerr << "warning: " << report.identifiability << identifiability_hint
              << "\n";
  }
  if (report.energy_scale < 1.0) {  // converged, then scaled
    std::cerr << "error: " << report.message << "\n";
    return 1;
  }
  if (!report.converged) {
    std::cerr << "error: the fit did not converge: " << report.message
              << " (solver: " << report.termination << ")\n";
    return 1;
  }
  return 0;
}

int FinishFit(const CommandArgs& args, const ModelParams& fitted,
              const FitReport& fit_report, const std::vector<double>& truth,
              const FitExtras& extras) {
  FitReport report = fit_report;
  ReportModelEnergy(fitted, &report);
  return FinishFit(
      report, truth, args.Get("out"),
      [&](std::string fit_json) {
        if (!extras.json.empty()) {
          nlohmann::ordered_json j = nlohmann::ordered_json::parse(fit_json);
          for (const auto& [key, text] : extras.json) {
            j[key] = nlohmann::ordered_json::parse(text);
          }
          fit_json = j.dump();
        }
        WriteParamFile(ParamFile{fitted, fit_json}, args.Get("out"));
      },
      extras.text,
      // A Lafortune fit has no --fix; its messages say what to do.
      std::holds_alternative<LafortuneModel>(fitted) ? "" : kFixHint);
}

namespace {

// FinishFit with the --tolerance report (may be null) added to "fit".
int Finish(const CommandArgs& args, const ModelParams& fitted,
           const FitReport& report, const std::vector<double>& truth,
           const SelectionReport* selection) {
  FitExtras extras;
  if (selection) {
    extras.text = SelectionReportText(*selection) + "\n";
    extras.json.emplace_back("selection", SelectionReportJson(*selection));
  }
  const int status = FinishFit(args, fitted, report, truth, extras);
  // A physically based model far from the data: a table on another scale
  // is the common cause (a thread fitted to CUReT: albedo 0, relative rms
  // 1.2).
  if (report.usable && report.relative_rms > 0.5 && !args.Has("fit-scale") &&
      !std::holds_alternative<SheenParams>(fitted)) {
    std::cerr << "hint: relative rms "
              << text_util::FormatNumber(report.relative_rms, 3)
              << ": if the table's values are not on a reflectance scale, "
                 "--fit-scale fits a factor on the model\n";
  }
  return status;
}

}  // namespace

int RunFit(int argc, char** argv) {
  // Lafortune and holes fits take other options (apps/cmd_fit_lafortune.cc,
  // apps/cmd_holes.cc).
  const std::string model_argument = ModelArgument(argc, argv);
  if (model_argument == "lafortune") return RunFitLafortune(argc, argv);
#ifdef CLOTHFIT_LIGHT
  if (model_argument == "holes") RunInFullBinary();  // a mask
#else
  if (model_argument == "holes") return RunFitHoles(argc, argv);
#endif
  CommandArgs args(
      "fit",
      "clothfit fit --model thread|cloth --data T.csv [--init P.json | "
      "--preset NAME] --out P.json [options]\n       clothfit fit --model "
      "auto --data T.csv [--fit-scale] [--folds K] --out P.json [options]\n"
      "       clothfit fit --model slab --data T.csv[,D.csv,...] [--init "
      "P.json] [--per-channel-tau] "
      "--out P.json [options]\n       clothfit fit --model sheen --data "
      "T.csv [--init P.json] --out P.json [options]\n       clothfit fit "
      "--model lafortune ... (see clothfit fit --model lafortune --help)\n     "
      "  "
      "clothfit fit --model holes ... (see clothfit fit --model holes "
      "--help)",
      "Fits a model to a measurement table with Ceres (Levenberg-Marquardt, "
      "automatic derivatives, bounds),\nwrites the parameters with a \"fit\" "
      "object (errors, standard deviations), and prints a summary.\nthread: "
      "without --init, a default multi-start grid (docs/fitting.md). cloth: "
      "the weave comes from\n--init or --preset; by default albedo, kd, "
      "gamma_s_deg, gamma_v_deg of every thread are free.\nslab: one or more "
      "tables, comma-separated: BSDF tables (reflection and/or transmission "
      "rows)\nand direct-transmittance tables; the summary and the \"fit\" "
      "object say whether the data are within\nthe model's regime "
      "(docs/slab.md).\nExit status 1 when "
      "the fit reaches no usable solution or does not converge.");
  args.Option("model", "M",
              "thread, cloth, slab, sheen, auto (or lafortune, holes); "
              "sheen: the glTF cloth material; auto: picks "
              "the family by held-out error (docs/fitting.md)");
  args.Option("data", "T.csv",
              "measurement table (docs/formats.md); slab: A.csv,B.csv,... ");
  args.Option("init", "P.json", "initial parameters");
  args.Option("preset", "NAME", "initial parameters from a preset (cloth)");
  args.Option("out", "P.json", "result parameter file");
  args.Option("fix", "A,B", "parameters held fixed (e.g. eta,kd or albedo)");
  args.Option("free", "A,B", "free only these parameters");
  args.Option("also-free", "A,B",
              "cloth: free these on top of the free set, e.g. the weave's "
              "freedoms rotation_deg,offsets_deg,diffuse,coverage "
              "(docs/fitting.md)");
  args.Option("design-points", "N",
              "cloth with its geometry or eta free: weave geometries of the "
              "start search's space-filling design, 0 to 100000 (default: " +
                  std::to_string(ClothFitOptions().design_points) + ")");
  AddSolverOptions(&args, SolverOptions(), true,
                   "threads for residual evaluation");
  args.Option(
      "starts", "N",
      "multi-start: solve from the N best-ranked starting points "
      "(default: " +
          std::to_string(ThreadFitOptions().solve_starts) + " thread, " +
          std::to_string(ClothFitOptions().solve_starts) +
          " cloth; cloth with its geometry free: more than " +
          std::to_string(ClothFitOptions().screen_keep) + " are screened by " +
          std::to_string(ClothFitOptions().screen_iterations) +
          " iterations and the best " +
          std::to_string(ClothFitOptions().screen_keep) + " solved on)");
  args.Option("truth", "P.json", "print these true values beside the fit");
  args.Flag("generic-start",
            "cloth: keep only the weave of --init/--preset (directions, "
            "coverages, offsets, eta) and start the threads from generic "
            "values");
  args.Option("tolerance", "REL",
              "pick the simplest configuration whose relative rms error is "
              "at most REL (docs/fitting.md)");
  args.Flag("fit-scale",
            "data on an arbitrary scale: also fit a factor on the model "
            "(reported as 'scale')");
  args.Flag("energy-bound",
            "thread, cloth, auto: fit and write the bounded model, which "
            "conserves energy on both sides (the default; docs/fitting.md)");
  args.Flag("paper-model",
            "thread, cloth, auto: fit and write the paper's model instead of "
            "the bounded one (it does not conserve energy toward grazing "
            "directions)");
  args.Flag("per-channel-tau", "slab: one tau per channel (r, g, b)");
  args.Flag("skip-invalid", "drop invalid table rows (reports how many)");
  args.Option("folds", "K",
              "auto: folds of the held-out selection over rows, 2 to 100 "
              "(default: 5)");
  if (!args.Parse(argc, argv, 2)) return 0;
  const std::string model = args.Required("model");
  for (const char* cloth_only : {"also-free", "design-points"}) {
    if (args.Has(cloth_only) && model != "cloth") {
      args.Fail(std::string("--") + cloth_only + " is for the cloth model");
    }
  }
  for (const char* flag : {"energy-bound", "paper-model"}) {
    if (args.Has(flag) && model != "thread" && model != "cloth" &&
        model != "auto") {
      args.Fail(std::string("--") + flag +
                " is for the thread, cloth and auto models");
    }
  }
  if (args.Has("paper-model") && args.Has("energy-bound")) {
    args.Fail("--paper-model and --energy-bound exclude each other");
  }
  CheckWritable(args.Required("out"));  // before the fit, not after
  const SolverOptions solver = ReadSolverOptions(args, true);
  if (model == "slab") return RunFitSlab(args, solver);
  if (model == "auto") return RunFitAuto(args, solver);
  if (args.Has("folds")) args.Fail("--folds is for --model auto");
  if (args.Has("per-channel-tau")) args.Fail("--per-channel-tau is for slab");
  const MeasurementTable table = ReadDataOption(args);
  if (model != "sheen") WarnArbitraryScale(args, table);
  const std::vector<std::string> fix = ListOption(args, "fix");
  const std::vector<std::string> free_only = ListOption(args, "free");
  int starts = 0;  // 0: the model's default
  if (args.Has("starts")) {
    const long n = args.GetInt("starts");
    if (n < 1 || n > 100) args.Fail("option '--starts': must be in [1, 100]");
    starts = static_cast<int>(n);
  }
  std::optional<double> tolerance;
  if (args.Has("tolerance")) {
    tolerance = args.GetDouble("tolerance");
    if (!(*tolerance > 0.0)) args.Fail("option '--tolerance': must be > 0");
  }
  std::optional<ParamFile> truth;
  if (args.Has("truth")) truth = ReadParamFile(args.Get("truth"));

  if (model == "thread") {
    ThreadFitOptions options;
    options.solver = solver;
    options.fix = fix;
    options.free_only = free_only;
    options.fit_scale = args.Has("fit-scale");
    options.energy_bound = !args.Has("paper-model");
    if (starts > 0) options.solve_starts = starts;
    if (args.Has("preset"))
      args.Fail("--preset gives cloth parameters; use --init");
    if (args.Has("init")) {
      const ParamFile init = ReadParamFile(args.Get("init"));
      if (!std::holds_alternative<ThreadParams>(init.params)) {
        args.Fail(args.Get("init") + ": expected a thread parameter file");
      }
      options.init = std::get<ThreadParams>(init.params);
    }
    std::vector<double> truth_values;
    if (truth && std::holds_alternative<ThreadParams>(truth->params)) {
      truth_values.resize(kThreadFlatSize);
      ToArray(std::get<ThreadParams>(truth->params), truth_values.data());
    }
    if (tolerance) {
      const ThreadSelection sel = SelectThreadModel(table, options, *tolerance);
      return Finish(args, sel.fit.params, sel.fit.report, truth_values,
                    &sel.report);
    }
    const ThreadFitResult r = FitThread(table, options);
    return Finish(args, r.params, r.report, truth_values, nullptr);
  }
  if (model == "cloth") {
    const ParamFile init = LoadModelOption(args, "init");
    if (!std::holds_alternative<ClothParams>(init.params)) {
      args.Fail("expected cloth initial parameters");
    }
    const ClothParams layout =
        args.Has("generic-start")
            ? GenericClothStart(std::get<ClothParams>(init.params))
            : std::get<ClothParams>(init.params);
    ClothFitOptions options;
    options.solver = solver;
    options.fix = fix;
    options.free_only = free_only;
    options.fit_scale = args.Has("fit-scale");
    options.energy_bound = !args.Has("paper-model");
    options.also_free = ListOption(args, "also-free");
    if (args.Has("design-points")) {
      const long n = args.GetInt("design-points");
      // 1000 points take ~12 s on a 200-row table: 10000 are minutes.
      if (n < 0 || n > 10000) {
        args.Fail("option '--design-points': must be in [0, 10000]");
      }
      options.design_points = static_cast<int>(n);
    }
    if (starts > 0) options.solve_starts = starts;
    std::vector<double> truth_values;
    if (truth && std::holds_alternative<ClothParams>(truth->params) &&
        std::get<ClothParams>(truth->params).threads.size() ==
            layout.threads.size()) {
      truth_values =
          ClothParameterValues(std::get<ClothParams>(truth->params), layout);
    }
    if (tolerance) {
      const ClothSelection sel =
          SelectClothModel(table, layout, options, *tolerance);
      WarnNotReflection(sel.fit.report, "cloth");
      // The chosen weave may have fewer samples: no per-entry truth column.
      return Finish(args, sel.fit.params, sel.fit.report, truth_values,
                    &sel.report);
    }
    const ClothFitResult r = FitCloth(table, layout, options);
    WarnNotReflection(r.report, "cloth");
    return Finish(args, r.params, r.report, truth_values, nullptr);
  }
  if (model == "sheen") {
    if (args.Has("preset") || args.Has("fit-scale") || tolerance) {
      args.Fail("--preset, --fit-scale and --tolerance are not for sheen");
    }
    SheenFitOptions options;
    options.solver = solver;
    options.fix = fix;
    options.free_only = free_only;
    if (starts > 0) options.solve_starts = starts;
    if (args.Has("init")) {
      const ParamFile init = ReadParamFile(args.Get("init"));
      if (!std::holds_alternative<SheenParams>(init.params)) {
        args.Fail(args.Get("init") + ": expected a sheen parameter file");
      }
      options.init = std::get<SheenParams>(init.params);
    }
    std::vector<double> truth_values;
    if (truth && std::holds_alternative<SheenParams>(truth->params)) {
      const SheenParams& p = std::get<SheenParams>(truth->params);
      truth_values.resize(FlatSize(p));
      ToArray(p, truth_values.data());
    }
    const SheenFitResult r = FitSheen(table, options);
    WarnNotReflection(r.report, "sheen");
    return Finish(args, r.params, r.report, truth_values, nullptr);
  }
  args.Fail(
      "option '--model': expected thread, cloth, slab, sheen, auto, "
      "lafortune or holes, got '" +
      text_util::EscapeControl(model) + "'" +
      text_util::DidYouMean(model, {"thread", "cloth", "slab", "sheen", "auto",
                                    "lafortune", "holes"}));
}

}  // namespace clothfit
