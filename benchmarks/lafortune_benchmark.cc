// Lafortune + lookup-table fits on virtual-gonioreflectometer data: the
// paper's workload - 32 x 32 texels, 64 views x 64 lights
// (n = 8), 2 lobes, all mip levels: 1,365 fits - must take under 60 s on
// the 2-core machine with peak memory under 2 GB; and the speed-accuracy
// trade-off over lobe count and iteration caps on a smaller grid.
//   build/benchmarks/lafortune_benchmark --benchmark_repetitions=3
//       --benchmark_report_aggregates_only=true      (one command line)
// Counters: fits/s, mean relative RMS error of level 0 (per sample, and
// of the per-view colour), solver iterations per fit, peak RSS (MB).
#include <benchmark/benchmark.h>
#include <sys/resource.h>

#include <cmath>
#include <map>

#include "data_synthetic/virtual_gonio.h"
#include "fitting/lafortune_mip.h"

namespace clothfit {
namespace {

const MeasurementTable& GonioTable(int texels) {
  static std::map<int, MeasurementTable> cache;
  auto it = cache.find(texels);
  if (it != cache.end()) return it->second;
  VirtualGonioOptions options;
  options.pattern = WeavePattern::kPlain;
  options.texels = texels;
  options.directions = 8;  // 64 directions: 64 views x 64 lights
  return cache[texels] = MeasureVirtualGonio(options);
}

double PeakMegabytes() {
  rusage usage;
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;  // Linux: kilobytes
}

void Run(benchmark::State& state, int texels, const LafortuneMipOptions& o) {
  const MeasurementTable& table = GonioTable(texels);
  double error = 0.0, view_error = 0.0, iterations = 0.0;
  int fits = 0;
  for (auto _ : state) {
    const LafortuneMipResult r = FitLafortuneMip(table, o);
    fits = r.fits;
    error = view_error = iterations = 0.0;
    for (const LafortuneFitResult& t : r.levels[0].texels) {
      error += t.report.relative_rms;
      view_error += t.report.view_relative_rms;
      iterations += t.report.iterations;
    }
    const double n = static_cast<double>(r.levels[0].texels.size());
    error /= n;
    view_error /= n;
    iterations /= n;
  }
  state.counters["fits_per_s"] =
      benchmark::Counter(fits, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["rel_rms"] = error;
  state.counters["view_rel_rms"] = view_error;
  state.counters["iterations"] = iterations;
  state.counters["peak_MB"] = PeakMegabytes();
}

// The paper's workload: 32 x 32 texels, 6 levels, 2 lobes, all cores.
void BM_PaperWorkload(benchmark::State& state) {
  LafortuneMipOptions o;
  o.fit.lobes = 2;
  o.mip = true;
  Run(state, 32, o);
}
BENCHMARK(BM_PaperWorkload)->Unit(benchmark::kSecond)->Iterations(1);

// Speed against accuracy, 8 x 8 texels (level 0, 64 fits, both cores):
// lobes K, the lookup table, and the solver's function tolerance (1e-6 is
// Ceres' default, 1e-5 clothfit's).
void BM_LobesLutTolerance(benchmark::State& state) {
  LafortuneMipOptions o;
  o.fit.lobes = static_cast<int>(state.range(0));
  o.fit.lookup_table = state.range(1) != 0;
  o.fit.function_tolerance =
      std::pow(10.0, -static_cast<double>(state.range(2)));
  o.mip = false;
  Run(state, 8, o);
}
BENCHMARK(BM_LobesLutTolerance)
    ->ArgsProduct({{0, 1, 2, 3}, {0, 1}, {4, 5, 6}})
    ->ArgNames({"lobes", "lut", "ftol_exp"})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

// The first-pass subsample and the iteration cap per pass, K = 2 with the
// lookup table.
void BM_SubsampleAndIterationCap(benchmark::State& state) {
  LafortuneMipOptions o;
  o.fit.lobes = 2;
  o.fit.first_pass_subsample = static_cast<int>(state.range(0));
  o.fit.max_iterations = static_cast<int>(state.range(1));
  o.mip = false;
  Run(state, 8, o);
}
BENCHMARK(BM_SubsampleAndIterationCap)
    ->ArgsProduct({{1, 4, 16}, {10, 50}})
    ->ArgNames({"subsample", "max_iters"})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

}  // namespace
}  // namespace clothfit

BENCHMARK_MAIN();
