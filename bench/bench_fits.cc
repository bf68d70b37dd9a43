#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "bench/bench_internal.h"
#include "bench/holes_problem.h"
#include "data_synthetic/holes_truth.h"
#include "fitting/cloth_fit.h"
#include "fitting/holes_fit.h"
#include "fitting/model_selection.h"
#include "fitting/slab_fit.h"
#include "fitting/thread_fit.h"
#include "holes/hole_texture.h"
#include "models/presets.h"

namespace clothfit {
namespace bench_internal {
namespace {

// Holes: the peer fits Algorithm 3.1 on the whole tile (linear in the
// counts, so the top level's nine counts are the model) from the default
// start, against clothfit's fit with the same method and level.
std::string RunHolesPeer(const BenchOptions& o, const MeasurementTable& table,
                         const MeasurementTable& held_out,
                         const HoleTexture& texture, const HolesParams& truth,
                         std::vector<BenchRow>* rows) {
  const HolesTile tile = HolesTileOf(texture, HoleMethod::kAlgorithm31);
  const LevelTexels& top = tile.texels;
  auto params_json = [&](const HolesParams& p) {
    nlohmann::ordered_json j;
    j["model"] = "holes";
    j["thickness_texels"] = p.thickness_texels;
    j["wall_color"] = {p.wall_color.x, p.wall_color.y, p.wall_color.z};
    j["counts"] = top.counts[0].counts;
    j["texels"] = top.area;
    return j.dump();
  };
  return RunPeer(o, "holes", "scipy least_squares method=alg31 level=top",
                 table, held_out, params_json(HolesParams()),
                 params_json(truth),
                 FitHoles(table, tile, HolesFitOptions()).report, rows);
}

}  // namespace

// Thread: the satin's warp thread, 2 % noise; knobs: solver starts and the
// iteration cap.
std::string BenchThread(const BenchOptions& o, std::vector<BenchRow>* rows) {
  ClothParams satin;
  GetPreset("polyester_satin_charmeuse", &satin);
  const ThreadParams truth = satin.threads[0].params;
  const Problem problem =
      MakeProblem(truth, o.quick ? 400 : 4000, true, o.seed, o.seed + 1000);
  const MeasurementTable& table = problem.table;
  const std::vector<TableRow>& held_out = problem.held_out;
  const std::vector<int> starts =
      o.quick ? std::vector<int>{1, 2} : std::vector<int>{1, 2, 4};
  const std::vector<int> caps =
      o.quick ? std::vector<int>{200} : std::vector<int>{10, 50, 200};
  auto run = [&](const ThreadFitOptions& fit) {
    const ThreadFitResult r = FitThread(table, fit);
    Outcome out;
    out.success = r.report.usable && r.report.converged;
    out.value_error = HeldOutError(r.params, truth, held_out, table.quantity);
    out.param_error =
        LargestRelativeError(FlatValues(r.params), FlatValues(truth));
    return out;
  };
  for (int s : starts) {
    for (int cap : caps) {
      const std::string config = "starts=" + std::to_string(s) +
                                 " max_iterations=" + std::to_string(cap);
      Say(o, "thread: " + config);
      ThreadFitOptions fit = PaperThreadFit();
      fit.solve_starts = s;
      fit.solver.max_iterations = cap;
      BenchRow row = Measure(o, [&]() { return run(fit); });
      row.model = "thread";
      row.config = config;
      row.group = "starts=" + std::to_string(s);
      row.is_default = s == ThreadFitOptions().solve_starts &&
                       cap == SolverOptions().max_iterations;
      rows->push_back(row);
    }
  }
  SweepLinearSolvers(
      o, "thread",
      [&](LinearSolver solver) {
        ThreadFitOptions fit = PaperThreadFit();
        fit.solver.linear_solver = solver;
        return run(fit);
      },
      rows);
  // The quick bench keeps it to the slab's peer (the cheapest).
  if (o.quick) return "";
  return RunModelPeer(o, "thread", problem, truth, ThreadParams(),
                      FitThread(table, PaperThreadFit()).report, rows);
}

// Cloth: the satin from the generic start, 2 % noise; knobs: the start
// search and the number of solver starts.
std::string BenchCloth(const BenchOptions& o, std::vector<BenchRow>* rows) {
  ClothParams truth;
  GetPreset("polyester_satin_charmeuse", &truth);
  const Problem problem =
      MakeProblem(truth, o.quick ? 300 : 3000, false, o.seed, o.seed + 2000);
  const MeasurementTable& table = problem.table;
  const std::vector<TableRow>& held_out = problem.held_out;
  const ClothParams start = GenericClothStart(truth);
  struct Knobs {
    bool multi_start;
    int starts;
  };
  auto run = [&](const ClothFitOptions& fit) {
    const ClothFitResult r = FitCloth(table, start, fit);
    Outcome out;
    out.success = r.report.usable && r.report.converged;
    out.value_error = HeldOutError(r.params, truth, held_out, table.quantity);
    out.param_error =
        LargestRelativeError(ClothParameterValues(r.params, truth),
                             ClothParameterValues(truth, truth));
    return out;
  };
  std::vector<Knobs> knobs = {{false, 1}, {true, 1}, {true, 2}};
  if (!o.quick) knobs.push_back({true, 4});
  for (const Knobs& k : knobs) {
    const std::string config = std::string("start_search=") +
                               (k.multi_start ? "on" : "off") +
                               " starts=" + std::to_string(k.starts);
    Say(o, "cloth: " + config);
    ClothFitOptions fit = PaperClothFit();
    fit.multi_start = k.multi_start;
    fit.solve_starts = k.starts;
    BenchRow row = Measure(o, [&]() { return run(fit); });
    row.model = "cloth";
    row.config = config;
    row.group = std::string("start search ") + (k.multi_start ? "on" : "off");
    const ClothFitOptions defaults;
    row.is_default = k.multi_start == defaults.multi_start &&
                     k.starts == defaults.solve_starts;
    rows->push_back(row);
  }
  SweepLinearSolvers(
      o, "cloth",
      [&](LinearSolver solver) {
        ClothFitOptions fit = PaperClothFit();
        fit.solver.linear_solver = solver;
        return run(fit);
      },
      rows);
  // Model size: each thread's tangent curve sampled at T points where it
  // has more offsets than that (as the --tolerance ladder does,
  // fitting/model_selection.h); the largest T is the weave as given.
  int given = 0;
  for (const ClothThread& th : start.threads) {
    given = std::max(given, static_cast<int>(th.offsets_deg.size()));
  }
  std::vector<int> sizes =
      o.quick ? std::vector<int>{1} : std::vector<int>{1, 2, 4};
  sizes.push_back(given);
  for (int t : sizes) {
    const ClothParams resampled = ResampleTangentCurves(start, t, nullptr);
    const std::string config =
        "tangent_samples=" + (t == given
                                  ? "as given (" + std::to_string(t) + ")"
                                  : std::to_string(t));
    Say(o, "cloth: " + config);
    BenchRow row = Measure(o, [&]() {
      const ClothFitResult r = FitCloth(table, resampled, PaperClothFit());
      Outcome out;
      out.success = r.report.usable && r.report.converged;
      out.value_error = HeldOutError(r.params, truth, held_out, table.quantity);
      return out;
    });
    row.model = "cloth";
    row.config = config;
    row.group = "tangent samples";
    row.size = t;
    row.default_size = t == given;  // the default fit of the weave as given
    rows->push_back(row);
  }
  // The cloth peer takes seconds even on the quick bench's table.
  if (o.quick) return "";
  return RunModelPeer(o, "cloth", problem, truth, start,
                      FitCloth(table, start, PaperClothFit()).report, rows);
}

// Slab: tau 0.05, albedo (0.4, 0.3, 0.2) (inside the single-scattering
// regime, docs/slab.md), reflection and transmission rows, 2 % noise;
// knobs: solver starts and one tau per channel.
std::string BenchSlab(const BenchOptions& o, std::vector<BenchRow>* rows) {
  const SlabParams truth = BenchSlabTruth();
  const Problem problem =
      MakeProblem(truth, o.quick ? 300 : 3000, true, o.seed, o.seed + 3000);
  const MeasurementTable& table = problem.table;
  const std::vector<TableRow>& held_out = problem.held_out;
  const std::vector<double> truth_values = FlatValues(truth);
  auto run = [&](const SlabFitOptions& fit) {
    const SlabFitResult r = FitSlab({table}, fit);
    Outcome out;
    out.success = r.report.usable && r.report.converged;
    out.value_error = HeldOutError(r.params, truth, held_out, table.quantity);
    out.param_error = LargestRelativeError(FlatValues(r.params), truth_values);
    return out;
  };
  for (int starts :
       o.quick ? std::vector<int>{1, 2} : std::vector<int>{1, 2, 4}) {
    for (bool per_channel : {false, true}) {
      const std::string config =
          "starts=" + std::to_string(starts) +
          " per_channel_tau=" + (per_channel ? "on" : "off");
      Say(o, "slab: " + config);
      SlabFitOptions fit;
      fit.solve_starts = starts;
      fit.per_channel_tau = per_channel;
      BenchRow row = Measure(o, [&]() { return run(fit); });
      row.model = "slab";
      row.config = config;
      row.group =
          std::string("per-channel tau ") + (per_channel ? "on" : "off");
      const SlabFitOptions defaults;
      row.is_default = starts == defaults.solve_starts &&
                       per_channel == defaults.per_channel_tau;
      rows->push_back(row);
    }
  }
  SweepLinearSolvers(
      o, "slab",
      [&](LinearSolver solver) {
        SlabFitOptions fit;
        fit.solver.linear_solver = solver;
        return run(fit);
      },
      rows);
  return RunModelPeer(o, "slab", problem, truth, SlabParams(),
                      FitSlab({table}, SlabFitOptions()).report, rows);
}

// Holes: the thickness of a random mask's opaque texels from ray-traced
// ground-truth transmittance at 5 x 4 views; held out: 4 other azimuths.
// Knobs: the method (Algorithm 3.1, the extension) and the pyramid level
// evaluated (0 or the top).
std::string BenchHoles(const BenchOptions& o, std::vector<BenchRow>* rows) {
  const int size = o.quick ? 16 : 64;
  const Mask mask = RandomMask(size, size, 0.5, o.seed);
  const HoleTexture texture = AnalyzeMask(mask, true);
  HolesParams truth;
  truth.thickness_texels = 0.8;
  const std::vector<double> thetas = {0.0, 15.0, 30.0, 45.0, 55.0};
  const int samples = o.quick ? 16 : 32;
  const MeasurementTable table =
      HolesTruthTable(mask, truth, thetas, {0.0, 90.0, 180.0, 270.0}, samples);
  const MeasurementTable held_out = HolesTruthTable(
      mask, truth, thetas, {45.0, 135.0, 225.0, 315.0}, samples);
  for (HoleMethod method : {HoleMethod::kAlgorithm31, HoleMethod::kExtension}) {
    for (int level : {0, kTopLevel}) {
      const std::string config = std::string("method=") +
                                 HoleMethodName(method) +
                                 " level=" + (level < 0 ? "top" : "0");
      Say(o, "holes: " + config);
      const HolesTile tile = HolesTileOf(texture, method, level);
      BenchRow row = Measure(o, [&]() {
        const HolesFitResult r = FitHoles(table, tile, HolesFitOptions());
        Outcome out;
        out.success = r.report.usable && r.report.converged;
        // Held out: the fitted thickness's transmittance (the same method)
        // against the ground truth at the other azimuths.
        out.value_error = HolesHeldOutError(r.params, tile, held_out);
        out.param_error =
            std::abs(r.params.thickness_texels - truth.thickness_texels) /
            truth.thickness_texels;
        return out;
      });
      row.model = "holes";
      row.config = config;
      row.group = HoleMethodName(method);
      row.is_default = method == HolesTile().method && level == kTopLevel;
      rows->push_back(row);
    }
  }
  return RunHolesPeer(o, table, held_out, texture, truth, rows);
}

}  // namespace bench_internal
}  // namespace clothfit
