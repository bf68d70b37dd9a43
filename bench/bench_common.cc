#include <malloc.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <string>

#include "bench/bench_internal.h"
#include "data_synthetic/synthetic_table.h"

namespace clothfit {
namespace bench_internal {
namespace {

double ProcessCpuSeconds() {
  timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

// A memory line of /proc/self/status ("VmRSS:", "VmHWM:") in MB; NaN
// where it is missing.
double StatusMb(const std::string& key) {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind(key, 0) == 0) {
      return std::atof(line.c_str() + key.size()) / 1024.0;  // kB
    }
  }
  return kNaN;
}

// The baseline of a measurement of the memory a run adds: the free memory
// of the allocator's arenas returned to the system (else a run reuses it
// unseen, or the process's earlier peak is reported), Linux's high-water
// mark VmHWM reset to the current resident size by writing "5" to
// /proc/self/clear_refs (proc(5)), and that size. NaN when the mark is
// still above the resident size (no reset allowed): the growth is then
// not measurable.
double StartPeakMemory() {
  malloc_trim(0);
  std::ofstream("/proc/self/clear_refs") << "5";
  const double resident = StatusMb("VmRSS:");
  return StatusMb("VmHWM:") <= resident + 1.0 ? resident : kNaN;
}

}  // namespace

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
  const double start_mb = StartPeakMemory();
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
  row.peak_mb = StatusMb("VmHWM:") - start_mb;
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

}  // namespace bench_internal
}  // namespace clothfit
