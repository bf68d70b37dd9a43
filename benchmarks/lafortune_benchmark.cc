// Lafortune + lookup-table fits on virtual-gonioreflectometer data
// (issue 4): the paper's workload - 32 x 32 texels, 64 views x 64 lights
// (n = 8), 2 lobes, all mip levels: 1,365 fits - must take under 60 s on
// the 2-core machine with peak memory under 2 GB; and the speed-accuracy
// trade-off over lobe count and iteration caps on a smaller grid.
//   build/benchmarks/lafortune_benchmark --benchmark_repetitions=3
//       --benchmark_report_aggregates_only=true      (one command line)
// Counters: fits/s, mean relative RMS error of level 0, peak RSS (MB).
#include <benchmark/benchmark.h>
#include <sys/resource.h>

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
  double error = 0.0;
  int fits = 0;
  for (auto _ : state) {
    const LafortuneMipResult r = FitLafortuneMip(table, o);
    fits = r.fits;
    error = 0.0;
    for (const TexelFit& t : r.levels[0].texels) error += t.relative_rms;
    error /= r.levels[0].texels.size();
  }
  state.counters["fits_per_s"] =
      benchmark::Counter(fits, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["rel_rms"] = error;
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

// Speed against accuracy: lobes K and the iteration cap, 8 x 8 texels.
void BM_LobesAndIterations(benchmark::State& state) {
  LafortuneMipOptions o;
  o.fit.lobes = static_cast<int>(state.range(0));
  o.fit.max_iterations = static_cast<int>(state.range(1));
  o.fit.lookup_table = state.range(2) != 0;
  o.mip = false;
  Run(state, 8, o);
}
BENCHMARK(BM_LobesAndIterations)
    ->ArgsProduct({{0, 1, 2, 3}, {5, 50}, {0, 1}})
    ->ArgNames({"lobes", "iters", "lut"})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

}  // namespace
}  // namespace clothfit

BENCHMARK_MAIN();
