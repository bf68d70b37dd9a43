// The options of clothfit fit --model lafortune and the end of a texel-map
// fit, shared by fit and by merge (which reads the fit options its parts
// record; docs/scale.md).
#include "apps/lafortune_options.h"

#include <cstdio>
#include <iostream>
#include <variant>

#include "apps/commands.h"
#include "io/input_error.h"
#include "io/params_json.h"

namespace clothfit {

CommandArgs LafortuneFitArgs() {
  CommandArgs args(
      "fit",
      "clothfit fit --model lafortune (--data T.csv | --stack M.csv) "
      "--out P.json|P.exr [--lobes K | --tolerance REL] [--mip] "
      "[--region X0,Y0,W,H] [options]",
      "Fits Lafortune lobes with a per-view lookup table T(v) (Daubert et "
      "al. 2001): a first pass of the lobes by Levenberg-Marquardt with T "
      "fixed,\nthen lobes and T jointly (T eliminated in closed form; "
      "--solve alternate: the paper's alternation). A table without s,t "
      "columns\ngives one model, written as a parameter file (JSON), with "
      "standard deviations of the lobes.\nA table with s,t columns "
      "(or an image stack) is fitted per texel in parallel, with --mip also "
      "per 2x2, 4x4, ... group down to 1x1,\nand written as a tiled, "
      "mip-mapped OpenEXR (one channel per parameter) with a JSON index "
      "(P.exr.json).");
  args.Option("model", "M", "lafortune");
  args.Option("data", "T.csv",
              "measurement table (docs/formats.md), s,t optional");
  args.Option("stack", "M.csv", "image-stack manifest instead of --data");
  args.Option("out", "P.json|P.exr",
              "result: JSON for one model, EXR per texel");
  args.Option("init", "P.json",
              "start from this Lafortune parameter file (its lobes; its "
              "lookup table when fitted on the same views); every texel "
              "starts from it");
  args.Option("lobes", "K",
              "number of lobes, 0 to 3 (default: --init's, or 2)");
  args.Option("tolerance", "REL",
              "per texel, the smallest K (0..3) whose relative rms error is "
              "at most REL");
  args.Option("select", "heldout",
              "heldout: choose by k-fold error over the table's lights the "
              "lobe count (0..3) and the lookup table (on/off) of one "
              "model, or with s,t columns and --mip the mip level a map "
              "supports");
  args.Option("folds", "K", "folds of --select heldout, 2 to 20", "5");
  args.Flag("mip", "also fit the mip levels (2x2 groups down to 1x1)");
  args.Option("region", "X0,Y0,W,H",
              "with --stack: fit only this block of texels (W, H powers of "
              "two, X0, Y0 multiples of them) and its mip levels, reading "
              "only that region of each image, into a part file for "
              "clothfit merge (docs/scale.md)");
  args.Flag("no-lut", "no lookup table (T = 1)");
  args.Flag("data-start",
            "also try a start scaled to the data and keep the better "
            "(slower; docs/lafortune.md)");
  args.Option("solve", "S",
              "joint (lobes and table in one solve, to the optimum; a texel "
              "whose optimum is not plausible is fitted by the alternation "
              "instead) or alternate (the paper's alternation of lobes and "
              "table; docs/lafortune.md)",
              "joint");
  args.Option("lut-threshold", "X",
              "stop alternating when T changes less than this (mean relative)",
              "0.1");
  args.Option("alternations", "N",
              "cap on lobe/T alternations (1: T as started, also for "
              "--solve joint)",
              "10");
  // The defaults of a texel fit: a few iterations per pass, the normal
  // equations (fitting/lafortune_fit.h), every core for the texels.
  const LafortuneMipOptions defaults;
  SolverOptions solver_defaults;
  solver_defaults.max_iterations = defaults.fit.max_iterations;
  solver_defaults.num_threads = defaults.threads;
  solver_defaults.linear_solver = defaults.fit.linear_solver;
  AddSolverOptions(&args, solver_defaults, false,
                   "texel fits in parallel (iterations: per pass)",
                   "table with a sigma column, else absolute (every row "
                   "alike; docs/lafortune.md)");
  args.Flag("skip-invalid", "drop invalid table rows (reports how many)");
  return args;
}

void ReadLafortuneFitOptions(const CommandArgs& args,
                             LafortuneFitSetup* setup) {
  LafortuneMipOptions& options = setup->options;
  std::optional<LafortuneModel>& init = setup->init;
  if (args.Has("init")) {
    const ParamFile file = ReadParamFile(args.Get("init"));
    if (!std::holds_alternative<LafortuneModel>(file.params)) {
      args.Fail(args.Get("init") +
                ": expected a lafortune parameter file, "
                "got " +
                ModelName(file.params));
    }
    init = std::get<LafortuneModel>(file.params);
    if (init->params.lobes.size() > 3) {
      throw InputError(args.Get("init") + ": key 'lobes': " +
                       std::to_string(init->params.lobes.size()) +
                       " lobes; the fit fits 0 to 3 (a start with more would "
                       "lose lobes)");
    }
  }
  long lobes = 2;
  if (args.Has("lobes")) {
    lobes = args.GetInt("lobes");
    if (lobes < 0 || lobes > 3) args.Fail("option '--lobes': must be 0 to 3");
    if (init && static_cast<size_t>(lobes) != init->params.lobes.size()) {
      args.Fail("option '--lobes': " + std::to_string(lobes) +
                " lobe(s), but --init " + args.Get("init") + " has " +
                std::to_string(init->params.lobes.size()));
    }
  } else if (init) {
    lobes = static_cast<long>(init->params.lobes.size());
  }
  options.fit.lobes = static_cast<int>(lobes);
  if (init) options.fit.start = &*init;
  options.fit.lookup_table = !args.Has("no-lut");
  options.fit.data_driven_start = args.Has("data-start");
  const std::string solve = args.Get("solve");
  if (solve == "joint") {
    options.fit.solve = LafortuneSolve::kJoint;
  } else if (solve == "alternate") {
    options.fit.solve = LafortuneSolve::kAlternate;
  } else {
    args.Fail("option '--solve': expected joint or alternate, got '" + solve +
              "'");
  }
  options.fit.lut_threshold = args.GetDouble("lut-threshold");
  if (!(options.fit.lut_threshold >= 0.0)) {
    args.Fail("option '--lut-threshold': must be >= 0");
  }
  const long alternations = args.GetInt("alternations");
  if (alternations < 1 || alternations > 1000) {
    args.Fail("option '--alternations': must be in [1, 1000]");
  }
  options.fit.max_alternations = static_cast<int>(alternations);
  const SolverOptions solver = ReadSolverOptions(args, false);
  options.fit.max_iterations = solver.max_iterations;
  options.threads = solver.num_threads;
  options.fit.linear_solver = solver.linear_solver;
  options.noise = solver.noise;
  options.mip = args.Has("mip");
  if (args.Has("tolerance")) {
    options.tolerance = args.GetDouble("tolerance");
    if (!(options.tolerance > 0.0))
      args.Fail("option '--tolerance': must be > 0");
  }
  setup->select = args.Has("select");
  const bool select = setup->select;
  if (select) {
    if (args.Get("select") != "heldout") {
      args.Fail("option '--select': expected heldout, got '" +
                args.Get("select") + "'");
    }
  }
  setup->folds = args.GetInt("folds");
  if (setup->folds < 2 || setup->folds > 20) {
    args.Fail("option '--folds': must be 2 to 20");
  }
}

int FinishLafortuneMip(const LafortuneMipResult& result, const ParamMipmap& map,
                       const std::string& out_path) {
  const LafortuneMipSummary summary = SummarizeLafortuneMip(result);
  std::printf(
      "lafortune fits: %d texel fit(s) over %zu level(s) in %.2f s "
      "(%.1f fits/s), worst relative rms %.4g\n",
      result.fits, result.levels.size(), result.seconds,
      result.fits / std::max(result.seconds, 1e-9), summary.worst_relative_rms);
  for (size_t l = 0; l < summary.levels.size(); ++l) {
    const LafortuneLevelSummary& level = summary.levels[l];
    std::printf(
        "  level %zu: %dx%d, %zu samples, mean relative rms %.4g (per-view "
        "colour %.4g), lobes 0/1/2/3: %d/%d/%d/%d, per fit %.1f "
        "alternations, %.0f solver iterations, %d at a search limit, "
        "largest directional albedo %.3g, %d scaled to conserve energy, "
        "%d by the alternation (joint optimum not plausible)\n",
        l, level.width, level.height, level.samples, level.mean_relative_rms,
        level.mean_view_relative_rms, level.lobe_counts[0],
        level.lobe_counts[1], level.lobe_counts[2], level.lobe_counts[3],
        level.mean_alternations, level.mean_iterations, level.at_search_limit,
        level.max_albedo, level.energy_scaled, level.solve_fallback);
  }
  WriteParamMipmap(map, out_path);
  std::printf("wrote %s and %s.json\n", out_path.c_str(), out_path.c_str());
  if (summary.not_converged > 0) {
    // A texel whose lookup table still moved at the cap is usable; the map
    // is written and the count reported (docs/decisions.md).
    std::cerr << "warning: " << summary.not_converged << " of " << result.fits
              << " texel fit(s) stopped at an iteration or alternation cap; "
                 "the first at "
              << summary.first_not_converged << "\n";
  }
  if (summary.at_search_limit > 0) {
    // The rule of the thread and cloth fits: written, but not converged.
    std::cerr << "error: " << summary.at_search_limit << " of " << result.fits
              << " texel fit(s) have a lobe entry at a search limit "
                 "(not converged); the first at "
              << summary.first_at_search_limit << "\n";
  }
  if (summary.energy_scaled > 0) {
    std::cerr << "error: " << summary.energy_scaled << " of " << result.fits
              << " texel fit(s) reflected more than they received and were "
                 "scaled down to conserve energy (not converged); the first "
                 "at "
              << summary.first_energy_scaled << "\n";
  }
  if (summary.unusable > 0) {
    std::cerr << "error: " << summary.unusable
              << " texel fit(s) reached no usable solution (zero in the "
                 "output); the first at "
              << summary.first_unusable << "\n";
    return 1;
  }
  return summary.at_search_limit > 0 || summary.energy_scaled > 0 ? 1 : 0;
}

}  // namespace clothfit
