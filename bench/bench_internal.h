// The internals of clothfit bench (bench/bench.h), shared by its files:
// timing, synthetic problems, the SciPy peers and one bench per fitter.
// Not installed.
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "bench/bench.h"
#include "fitting/cloth_fit.h"
#include "fitting/fit_result.h"
#include "fitting/linear_solver.h"
#include "fitting/thread_fit.h"
#include "io/table.h"
#include "models/evaluate.h"

namespace clothfit {
namespace bench_internal {

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// What one run of a configuration reports.
struct Outcome {
  double value_error = kNaN, param_error = kNaN;
  bool success = false;
};

double Median(std::vector<double> v);

// Runs `run` options.repeats times; the outcome is the last run's (the
// fits are deterministic). Wall and CPU time, and the resident memory the
// runs add at their peak (BenchRow::peak_mb).
BenchRow Measure(const BenchOptions& options,
                 const std::function<Outcome()>& run);

// Largest relative difference of the entries whose truth is not 0.
double LargestRelativeError(const std::vector<double>& fitted,
                            const std::vector<double>& truth);

// The flat vector of a parameter struct (models/params.h).
template <typename P>
std::vector<double> FlatValues(const P& p) {
  std::vector<double> x(FlatSize(p));
  ToArray(p, x.data());
  return x;
}

// Tells options.progress, if set.
void Say(const BenchOptions& o, const std::string& text);

// One row per linear solver (fitting/linear_solver.h; the quick bench: the
// two Eigen ones), the model's other knobs at their defaults; `run` fits
// with the given solver.
void SweepLinearSolvers(const BenchOptions& o, const std::string& model,
                        const std::function<Outcome(LinearSolver)>& run,
                        std::vector<BenchRow>* rows);

// The bench's thread and cloth tables are drawn from the paper's model
// (MakeProblem), and it times the fitter's knobs on them: fits of the
// paper's model, not of the bounded one (fitting/thread_fit.h; the bound's
// cost is measured on CUReT, docs/fitting.md).
inline ThreadFitOptions PaperThreadFit() {
  ThreadFitOptions o;
  o.energy_bound = false;
  return o;
}
inline ClothFitOptions PaperClothFit() {
  ClothFitOptions o;
  o.energy_bound = false;
  return o;
}

// A synthetic problem: the truth's table with 2 % noise, and held-out
// directions drawn from a second stream (wo over the whole sphere for the
// thread and slab models).
struct Problem {
  MeasurementTable table;
  std::vector<TableRow> held_out;
};
Problem MakeProblem(const ModelParams& truth, int rows, bool full_sphere,
                    uint64_t seed, uint64_t held_out_seed);

// The SciPy peers (benchmarks/peer/). Each returns why it did not run, or
// "" (its rows were added).
// Lafortune (scipy_lafortune.py) on a train/test split: a row per lobe
// count.
std::string RunPeer(const BenchOptions& o, const MeasurementTable& train,
                    const MeasurementTable& test, const std::vector<int>& lobes,
                    std::vector<BenchRow>* rows);
// A thread, cloth, slab or holes problem (scipy_models.py): `train` fitted
// from `params` (a parameter file as JSON text) over the parameter vector
// of `report`, scored against `held` (held-out views with the true
// values, `truth`).
std::string RunPeer(const BenchOptions& o, const std::string& model,
                    const std::string& config, const MeasurementTable& train,
                    const MeasurementTable& held, const std::string& params,
                    const std::string& truth, const FitReport& report,
                    std::vector<BenchRow>* rows);
// A thread, cloth or slab problem from `start`; the held-out values are
// the true model's.
std::string RunModelPeer(const BenchOptions& o, const std::string& model,
                         const Problem& problem, const ModelParams& truth,
                         const ModelParams& start, const FitReport& report,
                         std::vector<BenchRow>* rows);

// One bench per fitter: its rows, and why its peer did not run ("" when
// it did).
std::string BenchThread(const BenchOptions& o, std::vector<BenchRow>* rows);
std::string BenchCloth(const BenchOptions& o, std::vector<BenchRow>* rows);
std::string BenchSlab(const BenchOptions& o, std::vector<BenchRow>* rows);
std::string BenchHoles(const BenchOptions& o, std::vector<BenchRow>* rows);
std::string BenchLafortune(const BenchOptions& o, std::vector<BenchRow>* rows);

}  // namespace bench_internal
}  // namespace clothfit
