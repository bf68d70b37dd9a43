#include "bench/bench.h"

#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "bench/holes_problem.h"
#include "charts/chart.h"
#include "data_synthetic/holes_truth.h"
#include "data_synthetic/synthetic_table.h"
#include "data_synthetic/virtual_gonio.h"
#include "fitting/cloth_fit.h"
#include "fitting/holes_fit.h"
#include "fitting/lafortune_mip.h"
#include "fitting/linear_solver.h"
#include "fitting/model_selection.h"
#include "fitting/slab_fit.h"
#include "fitting/thread_fit.h"
#include "holes/hole_texture.h"
#include "io/atomic_file.h"
#include "io/params_json.h"
#include "io/table.h"
#include "io/text_util.h"
#include "models/presets.h"

namespace clothfit {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// What one run of a configuration reports.
struct Outcome {
  double value_error = kNaN, param_error = kNaN;
  bool success = false;
};

double ProcessCpuSeconds() {
  timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

// Peak resident memory (MB) since the last ResetPeakMemory: Linux's VmHWM,
// which writing "5" to /proc/self/clear_refs resets. Where that is not
// allowed the peak is the process's since it started.
void ResetPeakMemory() { std::ofstream("/proc/self/clear_refs") << "5"; }
double PeakMemoryMb() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmHWM:", 0) == 0) {
      return std::atof(line.c_str() + 6) / 1024.0;  // kB
    }
  }
  return kNaN;
}

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n == 0 ? kNaN : n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// Runs `run` options.repeats times; the outcome is the last run's (the
// fits are deterministic).
BenchRow Measure(const BenchOptions& options,
                 const std::function<Outcome()>& run) {
  std::vector<double> wall, cpu;
  BenchRow row;
  ResetPeakMemory();
  Outcome outcome;
  for (int r = 0; r < std::max(1, options.repeats); ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    const double c0 = ProcessCpuSeconds();
    outcome = run();
    cpu.push_back(ProcessCpuSeconds() - c0);
    wall.push_back(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0)
            .count());
  }
  row.repeats = static_cast<int>(wall.size());
  row.wall_median_s = Median(wall);
  row.wall_min_s = *std::min_element(wall.begin(), wall.end());
  row.wall_max_s = *std::max_element(wall.begin(), wall.end());
  row.cpu_median_s = Median(cpu);
  row.peak_mb = PeakMemoryMb();
  row.value_error = outcome.value_error;
  row.param_error = outcome.param_error;
  row.success = outcome.success;
  row.size = kNaN;
  return row;
}

// Largest relative difference of the entries whose truth is not 0.
double LargestRelativeError(const std::vector<double>& fitted,
                            const std::vector<double>& truth) {
  double worst = 0.0;
  for (size_t i = 0; i < truth.size() && i < fitted.size(); ++i) {
    if (truth[i] == 0.0) continue;
    worst =
        std::max(worst, std::abs(fitted[i] - truth[i]) / std::abs(truth[i]));
  }
  return worst;
}

// The flat vector of a parameter struct (models/params.h).
template <typename P>
std::vector<double> FlatValues(const P& p) {
  std::vector<double> x(FlatSize(p));
  ToArray(p, x.data());
  return x;
}

void Say(const BenchOptions& o, const std::string& text) {
  if (o.progress) o.progress(text);
}

// One row per linear solver (fitting/linear_solver.h; the quick bench: the
// two Eigen ones), the model's other knobs at their defaults; `run` fits
// with the given solver.
void SweepLinearSolvers(const BenchOptions& o, const std::string& model,
                        const std::function<Outcome(LinearSolver)>& run,
                        std::vector<BenchRow>* rows) {
  const std::vector<LinearSolver> solvers =
      o.quick ? std::vector<LinearSolver>{LinearSolver::kDenseQr,
                                          LinearSolver::kDenseNormalCholesky}
              : AllLinearSolvers();
  for (LinearSolver s : solvers) {
    const std::string config = "linear_solver=" + LinearSolverName(s);
    Say(o, model + ": " + config);
    BenchRow row = Measure(o, [&]() { return run(s); });
    row.model = model;
    row.config = config;
    row.group = "linear solver";
    rows->push_back(row);
  }
}

// A synthetic problem: the truth's table with 2 % noise, and held-out
// directions drawn from a second stream (wo over the whole sphere for the
// thread and slab models).
struct Problem {
  MeasurementTable table;
  std::vector<TableRow> held_out;
};

Problem MakeProblem(const ModelParams& truth, int rows, bool full_sphere,
                    uint64_t seed, uint64_t held_out_seed) {
  DirectionSampling sampling;
  sampling.rows = rows;
  sampling.full_sphere_out = full_sphere;
  SynthOptions synth;
  synth.noise = 0.02;
  Problem p;
  p.table = SyntheticTable(truth, sampling, synth, seed);
  Random random(held_out_seed);
  p.held_out = SampleDirections(sampling, &random);
  return p;
}

// Runs a peer script for o.repeats timed fits (`arguments` after the
// script, each quoted): o.repeats runs, or with `repeats_inside` one run
// that is given the count as a last argument and reports each fit's time
// in "seconds_each" (one Python start). *seconds receives the times (the
// fits only) and *result the last JSON object. Returns why it did not run,
// or "".
std::string RunPeerScript(const BenchOptions& o, const std::string& script,
                          std::vector<std::string> arguments,
                          bool repeats_inside, const std::string& json_out,
                          std::vector<double>* seconds,
                          nlohmann::json* result) {
  const int repeats = std::max(1, o.repeats);
  if (repeats_inside) arguments.push_back(std::to_string(repeats));
  std::string command = "'" + o.python + "' '" + script + "'";
  for (const std::string& a : arguments) command += " '" + a + "'";
  command += " > '" + json_out + "' 2>/dev/null";
  for (int r = 0; r < (repeats_inside ? 1 : repeats); ++r) {
    if (std::system(command.c_str()) != 0) {
      std::remove(json_out.c_str());
      return "SciPy peer skipped: '" + o.python + " " + script +
             "' failed (is python3-scipy installed?)";
    }
    *result = nlohmann::json::parse(ReadFileToString(json_out));
    if (repeats_inside) {
      *seconds = result->at("seconds_each").get<std::vector<double>>();
    } else {
      seconds->push_back(result->at("seconds").get<double>());
    }
  }
  std::remove(json_out.c_str());
  return "";
}

// A row of the peer: its time is the script's own (the fits, not Python's
// start or the CSV parsing), CPU = wall (one thread).
BenchRow PeerRow(const std::string& model, const std::string& config,
                 const std::vector<double>& seconds,
                 const nlohmann::json& result) {
  BenchRow row;
  row.model = model;
  row.config = config;
  row.group = "SciPy peer";
  row.repeats = static_cast<int>(seconds.size());
  row.wall_median_s = row.cpu_median_s = Median(seconds);
  row.wall_min_s = *std::min_element(seconds.begin(), seconds.end());
  row.wall_max_s = *std::max_element(seconds.begin(), seconds.end());
  row.peak_mb = kNaN;  // another process
  row.value_error = result.at("value_error").get<double>();
  row.param_error = result.value("param_error", kNaN);
  row.size = kNaN;
  row.success = result.value("success", true);
  return row;
}

std::string ScratchDir(const BenchOptions& o) {
  return o.scratch_dir.empty() ? "/tmp" : o.scratch_dir;
}

// The Lafortune peer (benchmarks/peer/scipy_lafortune.py) on the same
// train/test split: one row per lobe count.
std::string RunPeer(const BenchOptions& o, const MeasurementTable& train,
                    const MeasurementTable& test, const std::vector<int>& lobes,
                    std::vector<BenchRow>* rows) {
  if (o.peer_script.empty()) return "the SciPy peer was not asked for";
  const std::string dir = ScratchDir(o);
  const std::string train_csv = dir + "/peer_train.csv";
  const std::string test_csv = dir + "/peer_test.csv";
  WriteTable(train, train_csv);
  WriteTable(test, test_csv);
  std::string note;
  for (int k : lobes) {
    Say(o, "lafortune: SciPy peer, lobes=" + std::to_string(k));
    std::vector<double> seconds;
    nlohmann::json result;
    note = RunPeerScript(o, o.peer_script,
                         {train_csv, test_csv, std::to_string(k)}, false,
                         dir + "/peer_out.json", &seconds, &result);
    if (!note.empty()) break;
    rows->push_back(
        PeerRow("lafortune",
                "scipy least_squares lobes=" + std::to_string(k) + " lut=off",
                seconds, result));
  }
  std::remove(train_csv.c_str());
  std::remove(test_csv.c_str());
  return note;
}

// The peer of the thread, cloth and slab fits
// (benchmarks/peer/scipy_models.py, beside o.peer_script): the problem's
// table, its held-out directions with the true values, and the parameter
// vector as `report` (a clothfit fit of the problem) lists it - names,
// bounds, free entries - with the start and the truth as parameter files.
// The peer (scipy_models.py) on one problem: `train` fitted from `params`
// (a parameter file as JSON, the start) with the parameter vector of
// `report` (names, bounds, free entries), scored against `held` (held-out
// views with the true values); a row with `config` when it ran, else why
// not.
std::string RunPeer(const BenchOptions& o, const std::string& model,
                    const std::string& config, const MeasurementTable& train,
                    const MeasurementTable& held, const nlohmann::json& params,
                    const nlohmann::json& truth, const FitReport& report,
                    std::vector<BenchRow>* rows) {
  if (o.peer_script.empty()) return "the SciPy peer was not asked for";
  Say(o, model + ": SciPy peer");
  const std::string dir = ScratchDir(o);
  const std::string train_csv = dir + "/peer_" + model + "_train.csv";
  const std::string held_csv = dir + "/peer_" + model + "_held_out.csv";
  const std::string spec_json = dir + "/peer_" + model + "_spec.json";
  WriteTable(train, train_csv);
  WriteTable(held, held_csv);
  nlohmann::json spec;
  spec["params"] = params;
  spec["truth"] = truth;
  for (const ParameterReport& p : report.parameters) {
    spec["names"].push_back(p.name);
    spec["lower"].push_back(p.lower);
    spec["upper"].push_back(p.upper);
    spec["free"].push_back(p.free);
  }
  WriteFileAtomically(spec_json, spec.dump());
  const size_t slash = o.peer_script.rfind('/');
  const std::string script =
      (slash == std::string::npos ? std::string(".")
                                  : o.peer_script.substr(0, slash)) +
      "/scipy_models.py";
  std::vector<double> seconds;
  nlohmann::json result;
  const std::string note = RunPeerScript(
      o, script, {"fit", model, spec_json, train_csv, held_csv}, true,
      dir + "/peer_" + model + "_out.json", &seconds, &result);
  if (note.empty()) rows->push_back(PeerRow(model, config, seconds, result));
  for (const std::string& f : {train_csv, held_csv, spec_json}) {
    std::remove(f.c_str());
  }
  return note;
}

// The peer on a thread, cloth or slab problem, from `start`; the held-out
// values are the true model's.
std::string RunModelPeer(const BenchOptions& o, const std::string& model,
                         const Problem& problem, const ModelParams& truth,
                         const ModelParams& start, const FitReport& report,
                         std::vector<BenchRow>* rows) {
  MeasurementTable held = problem.table;
  held.has_sigma = false;
  held.rows = problem.held_out;
  for (TableRow& row : held.rows) {
    row.value = Evaluate(truth, row.wi, row.wo, held.quantity);
  }
  return RunPeer(o, model, "scipy least_squares", problem.table, held,
                 nlohmann::json::parse(FormatParamFile({start, ""})),
                 nlohmann::json::parse(FormatParamFile({truth, ""})), report,
                 rows);
}

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
      ThreadFitOptions fit;
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
        ThreadFitOptions fit;
        fit.solver.linear_solver = solver;
        return run(fit);
      },
      rows);
  // The quick bench keeps it to the slab's peer (the cheapest).
  if (o.quick) return "";
  return RunModelPeer(o, "thread", problem, truth, ThreadParams(),
                      FitThread(table, ThreadFitOptions()).report, rows);
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
    ClothFitOptions fit;
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
        ClothFitOptions fit;
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
      const ClothFitResult r = FitCloth(table, resampled, ClothFitOptions());
      Outcome out;
      out.success = r.report.usable && r.report.converged;
      out.value_error = HeldOutError(r.params, truth, held_out, table.quantity);
      return out;
    });
    row.model = "cloth";
    row.config = config;
    row.group = "tangent samples";
    row.size = t;
    rows->push_back(row);
  }
  // The cloth peer takes seconds even on the quick bench's table.
  if (o.quick) return "";
  return RunModelPeer(o, "cloth", problem, truth, start,
                      FitCloth(table, start, ClothFitOptions()).report, rows);
}

// Lafortune: virtual-gonio plain weave; every 4th light held out. Knobs:
// lobes K, the lookup table, the solver tolerance, threads, mip levels.
// The SciPy peer on the same train/test split: one row per lobe count, its
// time the script's own (the fits, not Python's start or the CSV parsing),
// CPU = wall (one thread). Returns why it did not run, or "".
// The held-out rows of each level-0 texel (s, t) of a gonio table.
using TexelRows = std::map<std::pair<int, int>, std::vector<size_t>>;

// The error of mip level `l` of a fit: for each texel (group) of the level,
// the relative RMS of its model at the held-out rows of all the level-0
// texels it pools (the group a level-0 texel joins as FitLafortuneMip
// pools them: x -> min(x / 2, width - 1) per level); the mean over the
// level's texels. *usable: every texel of the level fitted.
double LevelError(const LafortuneMipResult& r, size_t l,
                  const MeasurementTable& test, const ViewIndex& test_views,
                  const TexelRows& test_rows, bool* usable) {
  const LafortuneLevel& level = r.levels[l];
  std::vector<std::vector<size_t>> pooled(level.texels.size());
  for (const auto& [texel, indices] : test_rows) {
    int x = texel.first, y = texel.second;
    for (size_t k = 1; k <= l; ++k) {
      x = std::min(x / 2, r.levels[k].width - 1);
      y = std::min(y / 2, r.levels[k].height - 1);
    }
    std::vector<size_t>& to = pooled[y * level.width + x];
    to.insert(to.end(), indices.begin(), indices.end());
  }
  *usable = true;
  double sum = 0.0;
  int n = 0;
  for (size_t i = 0; i < level.texels.size(); ++i) {
    *usable = *usable && level.texels[i].report.usable;
    double rms = 0.0, rel = 0.0;
    LafortuneErrors(level.texels[i].params, test, test_views, pooled[i], &rms,
                    &rel);
    sum += rel;
    ++n;
  }
  return n ? sum / n : kNaN;
}

// Model size over mip levels: the default fit with all levels, timed
// (o.repeats runs) level by level; per level a row of the model
// "lafortune_mip" with its time, its error against the held-out rows
// (LevelError) and its size = texels of the level.
void BenchMipLevels(const BenchOptions& o, const MeasurementTable& train,
                    const MeasurementTable& test, const ViewIndex& test_views,
                    const TexelRows& test_rows, std::vector<BenchRow>* rows) {
  Say(o, "lafortune: mip levels");
  LafortuneMipOptions fit;
  fit.mip = true;
  std::vector<std::vector<double>> seconds;  // [level][run]
  LafortuneMipResult r;
  for (int run = 0; run < std::max(1, o.repeats); ++run) {
    r = FitLafortuneMip(train, fit);
    seconds.resize(r.levels.size());
    for (size_t l = 0; l < r.levels.size(); ++l) {
      seconds[l].push_back(r.levels[l].seconds);
    }
  }
  for (size_t l = 0; l < r.levels.size(); ++l) {
    const LafortuneLevel& level = r.levels[l];
    BenchRow row;
    row.model = "lafortune_mip";
    row.config = "level=" + std::to_string(l) + " (" +
                 std::to_string(level.width) + " x " +
                 std::to_string(level.height) + ")";
    row.label = "level " + std::to_string(l);
    row.group = "lobes=2 lut=on";
    row.repeats = static_cast<int>(seconds[l].size());
    row.wall_median_s = Median(seconds[l]);
    row.wall_min_s = *std::min_element(seconds[l].begin(), seconds[l].end());
    row.wall_max_s = *std::max_element(seconds[l].begin(), seconds[l].end());
    row.cpu_median_s = kNaN;  // the level's share is not measured
    row.peak_mb = kNaN;
    row.value_error =
        LevelError(r, l, test, test_views, test_rows, &row.success);
    row.param_error = kNaN;
    row.size = static_cast<double>(level.texels.size());
    row.is_default = l == 0;
    rows->push_back(row);
  }
}

std::string BenchLafortune(const BenchOptions& o, std::vector<BenchRow>* rows) {
  VirtualGonioOptions gonio;
  gonio.texels = o.quick ? 2 : 8;
  gonio.directions = o.quick ? 4 : 8;
  gonio.seed = o.seed;
  const MeasurementTable all = MeasureVirtualGonio(gonio);
  // Rows are ordered texel, view, light: the light index is the row index
  // modulo the number of lights.
  const size_t lights =
      static_cast<size_t>(gonio.directions) * gonio.directions;
  MeasurementTable train = all, test = all;
  train.rows.clear();
  test.rows.clear();
  for (size_t i = 0; i < all.rows.size(); ++i) {
    (i % lights % 4 == 3 ? test : train).rows.push_back(all.rows[i]);
  }
  const ViewIndex test_views(test);
  TexelRows test_rows;
  for (size_t i = 0; i < test.rows.size(); ++i) {
    test_rows[{test.rows[i].s, test.rows[i].t}].push_back(i);
  }
  // Level 0's error: the mean over texels of the relative RMS at their
  // held-out rows.
  auto run = [&](const LafortuneMipOptions& fit) {
    const LafortuneMipResult r = FitLafortuneMip(train, fit);
    Outcome out;
    out.value_error =
        LevelError(r, 0, test, test_views, test_rows, &out.success);
    return out;
  };
  struct Knobs {
    int lobes;
    bool lut;
    int ftol_exp;
    int threads;
    bool mip;
  };
  std::vector<Knobs> knobs;
  for (int k :
       o.quick ? std::vector<int>{0, 2} : std::vector<int>{0, 1, 2, 3}) {
    for (bool lut : {false, true}) {
      for (int e : o.quick ? std::vector<int>{5} : std::vector<int>{4, 5, 6}) {
        knobs.push_back({k, lut, e, 0, false});
      }
    }
  }
  if (!o.quick) {
    knobs.push_back({2, true, 5, 1, false});
    knobs.push_back({2, true, 5, 0, true});
  }
  for (const Knobs& k : knobs) {
    std::ostringstream config;
    config << "lobes=" << k.lobes << " lut=" << (k.lut ? "on" : "off")
           << " tolerance=1e-" << k.ftol_exp << " threads="
           << (k.threads == 0 ? std::string("all") : std::to_string(k.threads))
           << " mip=" << (k.mip ? "on" : "off");
    Say(o, "lafortune: " + config.str());
    LafortuneMipOptions fit;
    fit.fit.lobes = k.lobes;
    fit.fit.lookup_table = k.lut;
    fit.fit.function_tolerance = std::pow(10.0, -k.ftol_exp);
    fit.threads = k.threads;
    fit.mip = k.mip;
    BenchRow row = Measure(o, [&]() { return run(fit); });
    row.model = "lafortune";
    row.config = config.str();
    row.group = std::string("lut=") + (k.lut ? "on" : "off");
    if (k.ftol_exp == 5 && k.threads == 0 && !k.mip) row.size = k.lobes;
    row.is_default =
        k.lobes == 2 && k.lut && k.ftol_exp == 5 && k.threads == 0 && !k.mip;
    rows->push_back(row);
  }
  SweepLinearSolvers(
      o, "lafortune",
      [&](LinearSolver solver) {
        LafortuneMipOptions fit;
        fit.mip = false;
        fit.fit.linear_solver = solver;
        return run(fit);
      },
      rows);
  BenchMipLevels(o, train, test, test_views, test_rows, rows);
  return RunPeer(o, train, test,
                 o.quick ? std::vector<int>{2} : std::vector<int>{1, 2}, rows);
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
    nlohmann::json j;
    j["model"] = "holes";
    j["thickness_texels"] = p.thickness_texels;
    j["wall_color"] = {p.wall_color.x, p.wall_color.y, p.wall_color.z};
    j["counts"] = top.counts[0].counts;
    j["texels"] = top.area;
    return j;
  };
  return RunPeer(o, "holes", "scipy least_squares method=alg31 level=top",
                 table, held_out, params_json(HolesParams()),
                 params_json(truth),
                 FitHoles(table, tile, HolesFitOptions()).report, rows);
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

bool Wanted(const BenchOptions& o, const std::string& model) {
  return o.models.empty() ||
         std::find(o.models.begin(), o.models.end(), model) != o.models.end();
}

std::string Number(double v) {
  return std::isfinite(v) ? text_util::FormatNumber(v) : "nan";
}

// Four significant digits, for the summary's tables.
std::string Short(double v) {
  if (!std::isfinite(v)) return "nan";
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.4g", v);
  return buffer;
}

}  // namespace

SlabParams BenchSlabTruth() {
  SlabParams p;
  p.tau = glm::dvec3(0.05);
  p.albedo = glm::dvec3(0.4, 0.3, 0.2);
  return p;
}

double HeldOutError(const ModelParams& fitted, const ModelParams& truth,
                    const std::vector<TableRow>& rows, Quantity q) {
  double se = 0.0, ss = 0.0;
  for (const TableRow& row : rows) {
    const glm::dvec3 a = Evaluate(fitted, row.wi, row.wo, q);
    const glm::dvec3 b = Evaluate(truth, row.wi, row.wo, q);
    se += glm::dot(a - b, a - b);
    ss += glm::dot(b, b);
  }
  return ss > 0.0 ? std::sqrt(se / ss) : kNaN;
}

std::vector<BenchRow> RunBench(const BenchOptions& options,
                               std::string* peer_note) {
  std::vector<BenchRow> rows;
  // The first reason a peer did not run (the same for all, as a rule).
  std::string note;
  auto keep = [&](const std::string& n) {
    if (note.empty()) note = n;
  };
  if (Wanted(options, "thread")) keep(BenchThread(options, &rows));
  if (Wanted(options, "cloth")) keep(BenchCloth(options, &rows));
  if (Wanted(options, "slab")) keep(BenchSlab(options, &rows));
  if (Wanted(options, "holes")) keep(BenchHoles(options, &rows));
  if (Wanted(options, "lafortune")) keep(BenchLafortune(options, &rows));
  if (peer_note) *peer_note = note;
  return rows;
}

void WriteBenchCsv(const std::vector<BenchRow>& rows, const std::string& path) {
  std::ostringstream out;
  out << "model,config,default,repeats,wall_median_s,wall_min_s,wall_max_s,"
         "cpu_median_s,peak_mb,value_error,param_error,size,success\n";
  for (const BenchRow& r : rows) {
    out << r.model << ",\"" << r.config << "\"," << (r.is_default ? 1 : 0)
        << "," << r.repeats << "," << Number(r.wall_median_s) << ","
        << Number(r.wall_min_s) << "," << Number(r.wall_max_s) << ","
        << Number(r.cpu_median_s) << "," << Number(r.peak_mb) << ","
        << Number(r.value_error) << "," << Number(r.param_error) << ","
        << Number(r.size) << "," << (r.success ? 1 : 0) << "\n";
  }
  WriteFileAtomically(path, out.str());
}

double ToleranceChoice(const std::vector<BenchRow>& rows, double slack) {
  double best = std::numeric_limits<double>::infinity();
  for (const BenchRow& r : rows) {
    if (std::isfinite(r.size) && std::isfinite(r.value_error)) {
      best = std::min(best, r.value_error);
    }
  }
  double choice = kNaN;
  for (const BenchRow& r : rows) {
    if (std::isfinite(r.size) && r.value_error <= best * (1.0 + slack) &&
        !(r.size >= choice)) {
      choice = r.size;
    }
  }
  return choice;
}

std::vector<std::string> WriteBenchReport(const std::vector<BenchRow>& rows,
                                          const BenchOptions& options,
                                          const std::string& dir,
                                          const std::string& peer_note) {
  std::vector<std::string> files;
  std::vector<std::string> models;
  for (const BenchRow& r : rows) {
    if (std::find(models.begin(), models.end(), r.model) == models.end()) {
      models.push_back(r.model);
    }
  }
  constexpr double kSlack = 0.02;
  std::ostringstream md;
  md << "# clothfit bench" << (options.quick ? " (quick)" : "") << "\n\n"
     << "Each configuration ran " << std::max(1, options.repeats)
     << " time(s); wall time is the median with [min, max]. Errors are "
        "against truth held out from the fit (docs/bench.md).\n";
  for (const std::string& model : models) {
    std::vector<BenchRow> mine;
    for (const BenchRow& r : rows) {
      if (r.model == model) mine.push_back(r);
    }
    ScatterChart speed;
    speed.title = model + ": speed against accuracy";
    speed.x_label = "wall time per fit run [s]";
    speed.y_label = "held-out relative RMS error";
    speed.log_x = true;
    speed.pareto = true;
    std::map<std::string, size_t> series_of;
    for (const BenchRow& r : mine) {
      auto [it, added] = series_of.emplace(r.group, speed.series.size());
      if (added) {
        speed.series.push_back(ScatterSeries());
        speed.series.back().name = r.group;
        speed.series.back().pareto = true;
      }
      ChartPoint p;
      p.x = r.wall_median_s;
      p.y = r.value_error;
      p.highlight = r.is_default;
      speed.series[it->second].points.push_back(p);
    }
    const std::string speed_png = dir + "/" + model + "_speed_accuracy.png";
    WriteScatterChartPng(speed, speed_png);
    files.push_back(speed_png);

    md << "\n## " << model << "\n\n![speed against accuracy](" << model
       << "_speed_accuracy.png)\n";
    // The peer beside clothfit's same problem: the configuration its
    // config names after the solver ("scipy least_squares method=alg31
    // level=top"), else the default (Lafortune: the same lobe count K
    // without lookup table).
    const std::string kPeerName = "scipy least_squares";
    for (const BenchRow& peer : mine) {
      if (peer.group != "SciPy peer") continue;
      const size_t at = peer.config.find("lobes=");
      const std::string lobes =
          at == std::string::npos ? "" : peer.config.substr(at, 7);
      const std::string twin = peer.config.size() > kPeerName.size()
                                   ? peer.config.substr(kPeerName.size() + 1)
                                   : "";
      for (const BenchRow& r : mine) {
        if (r.group == "SciPy peer") continue;
        const bool same =
            !lobes.empty()
                ? r.config.rfind(lobes + " lut=off tolerance=1e-5 threads=all",
                                 0) == 0
            : twin.empty() ? r.is_default
                           : r.config == twin;
        if (!same) continue;
        md << "\nSciPy peer" << (lobes.empty() ? "" : ", " + lobes)
           << (!lobes.empty() ? " without lookup table"
               : twin.empty() ? " against clothfit's default"
                              : " against clothfit's " + twin)
           << ": " << Short(peer.cpu_median_s) << " s CPU against clothfit's "
           << Short(r.cpu_median_s) << " s ("
           << Short(peer.cpu_median_s / r.cpu_median_s)
           << " x); held-out error " << Short(peer.value_error) << " against "
           << Short(r.value_error) << " (difference "
           << Short(peer.value_error - r.value_error) << ").\n";
      }
    }
    const bool has_peer = model == "thread" || model == "cloth" ||
                          model == "slab" || model == "lafortune" ||
                          model == "holes";
    if (has_peer && !peer_note.empty()) md << "\n" << peer_note << ".\n";
    bool sized = false;
    for (const BenchRow& r : mine) sized = sized || std::isfinite(r.size);
    if (sized) {
      ScatterChart size;
      size.title = model + ": error against model size";
      size.x_label = model == "cloth"           ? "tangent samples T per thread"
                     : model == "lafortune_mip" ? "texels of the mip level"
                                                : "lobes K";
      size.log_x = model == "lafortune_mip";
      size.y_label = "held-out relative RMS error";
      std::map<std::string, size_t> size_series;
      for (const BenchRow& r : mine) {
        if (!std::isfinite(r.size)) continue;
        auto [it, added] = size_series.emplace(r.group, size.series.size());
        if (added) {
          size.series.push_back(ScatterSeries());
          size.series.back().name = r.group;
          size.series.back().lines = true;
        }
      }
      for (auto& [group, index] : size_series) {
        std::vector<BenchRow> in_group;
        for (const BenchRow& r : mine) {
          if (std::isfinite(r.size) && r.group == group) in_group.push_back(r);
        }
        std::sort(in_group.begin(), in_group.end(),
                  [](const BenchRow& a, const BenchRow& b) {
                    return a.size < b.size;
                  });
        const double pick = ToleranceChoice(in_group, kSlack);
        for (const BenchRow& r : in_group) {
          ChartPoint p;
          p.x = r.size;
          p.y = r.value_error;
          p.highlight = r.size == pick;
          p.label = r.label;
          size.series[index].points.push_back(p);
        }
        md << "\n`--tolerance` just above the best error of " << group << " (+"
           << kSlack * 100 << " %) picks size " << Number(pick) << ".\n";
      }
      const std::string size_png = dir + "/" + model + "_size.png";
      WriteScatterChartPng(size, size_png);
      files.push_back(size_png);
      md << "\n![error against model size](" << model << "_size.png)\n";
    }
    md << "\n| config | wall median [min, max] s | CPU s | peak MB | "
          "held-out error | parameter error | converged |\n"
          "|---|---|---|---|---|---|---|\n";
    for (const BenchRow& r : mine) {
      md << "| " << r.config << (r.is_default ? " **(default)**" : "") << " | "
         << Short(r.wall_median_s) << " [" << Short(r.wall_min_s) << ", "
         << Short(r.wall_max_s) << "] | " << Short(r.cpu_median_s) << " | "
         << Short(r.peak_mb) << " | " << Short(r.value_error) << " | "
         << Short(r.param_error) << " | " << (r.success ? "yes" : "no")
         << " |\n";
    }
  }
  const std::string summary = dir + "/summary.md";
  WriteFileAtomically(summary, md.str());
  files.push_back(summary);
  return files;
}

}  // namespace clothfit
