#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <nlohmann/json.hpp>

#include "bench/bench_internal.h"
#include "io/atomic_file.h"
#include "io/params_json.h"

namespace clothfit {
namespace bench_internal {
namespace {

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

}  // namespace

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
                    const MeasurementTable& held, const std::string& params,
                    const std::string& truth, const FitReport& report,
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
  spec["params"] = nlohmann::json::parse(params);
  spec["truth"] = nlohmann::json::parse(truth);
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
                 FormatParamFile({start, ""}), FormatParamFile({truth, ""}),
                 report, rows);
}

}  // namespace bench_internal
}  // namespace clothfit
