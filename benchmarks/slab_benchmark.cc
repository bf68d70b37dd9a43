// Speed of the slab fit and Monte Carlo (the model's own speed is
// model_benchmark's BM_SlabBsdf): the fit of a 10,000-row table (random
// directions, reflection and transmission, 2 % noise; start grid included),
// and Monte Carlo photons per second on one thread and on all cores. For
// medians and spread:
//   build/benchmarks/slab_benchmark --benchmark_repetitions=7
//       --benchmark_report_aggregates_only=true      (one command line)
#include <benchmark/benchmark.h>

#include "data_synthetic/slab_monte_carlo.h"
#include "data_synthetic/synthetic_table.h"
#include "fitting/slab_fit.h"

namespace clothfit {
namespace {

SlabParams Params() {
  SlabParams p;
  p.tau = glm::dvec3(0.08);
  p.albedo = {0.9, 0.6, 0.3};
  return p;
}

void BM_SlabFit(benchmark::State& state) {
  DirectionSampling sampling;
  sampling.rows = static_cast<int>(state.range(0));
  SynthOptions synth;
  synth.noise = 0.02;
  const MeasurementTable table = SyntheticTable(Params(), sampling, synth, 11);
  for (auto _ : state) {
    const SlabFitResult r = FitSlab({table}, SlabFitOptions());
    if (!r.report.converged) state.SkipWithError("fit did not converge");
    benchmark::DoNotOptimize(r.params.tau.x);
  }
}
BENCHMARK(BM_SlabFit)->Arg(10000)->Unit(benchmark::kMillisecond);

// Photons per second: 6 beams x 9 views, all orders, per-channel albedo.
void BM_SlabMonteCarlo(benchmark::State& state) {
  SlabMonteCarloOptions o;
  o.params = Params();
  o.params.tau = glm::dvec3(state.range(0) / 100.0);
  o.photons = 20000;
  o.threads = static_cast<int>(state.range(1));
  for (auto _ : state) {
    benchmark::DoNotOptimize(RunSlabMonteCarlo(o).beams.size());
  }
  state.SetItemsProcessed(state.iterations() * o.photons *
                          static_cast<int64_t>(o.theta_i_deg.size()));
}
BENCHMARK(BM_SlabMonteCarlo)
    ->Args({5, 1})  // tau = 0.05, one thread
    ->Args({100, 1})
    ->Args({5, 0})  // all cores
    ->Args({100, 0})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace clothfit

BENCHMARK_MAIN();
