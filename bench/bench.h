// clothfit bench: sweeps over the knobs that trade speed for
// accuracy for each fitter, on synthetic data whose truth is held out from
// the fit, timed over repeated runs (median and spread, since the machine
// is shared), and written as a CSV, PNG charts and a Markdown summary.
//
// Errors: `value_error` is the relative RMS of the fitted model against the
// truth at held-out directions (thread, cloth: the true model's values at
// directions the fit never saw; Lafortune: virtual-gonio rows of held-out
// lights, every 4th, which the fit never saw); `param_error` the largest
// relative error of a free parameter against the truth (NaN where the data
// have no parameter truth, as the gonio's).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "io/table.h"
#include "models/evaluate.h"

namespace clothfit {

struct BenchOptions {
  bool quick = false;  // seconds, for the test suite: small data, few knobs
  int repeats = 3;     // timed runs per configuration (median, min, max)
  // Fitters to run ("thread", "cloth", "lafortune", "slab", "holes");
  // empty = all. The stability study runs those of them it has.
  std::vector<std::string> models;
  uint64_t seed = 1;
  std::function<void(const std::string&)> progress;  // may be empty
  // The peer: SciPy's least_squares on the same Lafortune problems
  // (benchmarks/peer/scipy_lafortune.py); skipped with a message (in
  // peer_note) where Python 3 with SciPy is missing. Empty: no peer.
  std::string peer_script;
  std::string python = "python3";
  std::string scratch_dir;  // where the peer's input tables are written
};

struct BenchRow {
  std::string model;
  std::string config;  // "knob=value ..." in a fixed order
  bool is_default = false;
  int repeats = 0;
  double wall_median_s = 0.0, wall_min_s = 0.0, wall_max_s = 0.0;
  double cpu_median_s = 0.0;  // process CPU time (all threads)
  // Growth of the resident memory over the runs: peak (VmHWM, reset
  // before the first run) less the resident size at the start, after the
  // allocator returned its free memory (bench_common.cc Measure); NaN
  // where it is not measured.
  double peak_mb = 0.0;
  double value_error = 0.0;  // held-out relative RMS (see above)
  double param_error = 0.0;  // NaN where there is no parameter truth
  double size = 0.0;         // model size (lobes; NaN where not swept)
  bool success = false;      // the fit reported usable and converged
  // The default configuration again as a point of a size sweep (ringed in
  // the size chart; is_default rings it in the speed chart, once).
  bool default_size = false;
  std::string group;  // series of the charts (e.g. "lut=on")
  std::string label;  // beside the point in the size chart
};

// peer_note (may be null): what became of the peer ("" when it ran).
std::vector<BenchRow> RunBench(const BenchOptions& options,
                               std::string* peer_note = nullptr);

// The slab of the bench and the stability study: tau 0.05, albedo (0.4,
// 0.3, 0.2), inside the single-scattering regime (docs/slab.md).
SlabParams BenchSlabTruth();

// Relative RMS of `fitted` against `truth` at the rows' directions (the
// quantity q): the held-out error of the thread and cloth fits.
double HeldOutError(const ModelParams& fitted, const ModelParams& truth,
                    const std::vector<TableRow>& rows, Quantity q);

// One row per configuration; throws InputError when it cannot be written.
void WriteBenchCsv(const std::vector<BenchRow>& rows, const std::string& path);

// Per model: `<dir>/<model>_speed_accuracy.png` (log wall time against the
// held-out error, Pareto front, default ringed) and, where a size was
// swept, `<dir>/<model>_size.png` (error against model size, the default
// ringed; bench/bench_charts.h); then `<dir>/summary.md` (with the size
// `--tolerance` picks). Returns the files written.
std::vector<std::string> WriteBenchReport(const std::vector<BenchRow>& rows,
                                          const BenchOptions& options,
                                          const std::string& dir,
                                          const std::string& peer_note = "");

// The smallest size whose error is within `slack` (relative) of the best
// error among the rows of one model and group: the model `--tolerance`
// would choose with the tolerance set just above the best reachable error.
// NaN when no row has a size.
double ToleranceChoice(const std::vector<BenchRow>& rows, double slack);

}  // namespace clothfit
