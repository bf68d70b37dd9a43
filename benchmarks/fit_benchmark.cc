// Fit speed: a 10,000-row thread table in under 0.5 s and a
// 5,000-row two-thread cloth table in under 2 s on one core, from the
// default start (the start search included), of the paper's model (the
// bounded fit's cost: docs/fitting.md). Tables are synthetic with 2 %
// noise, of the paper's model; each iteration runs the whole fit. For medians
// and spread:
//   build/benchmarks/fit_benchmark --benchmark_repetitions=7
//       --benchmark_report_aggregates_only=true      (one command line)
#include <benchmark/benchmark.h>

#include "data_synthetic/synthetic_table.h"
#include "fitting/cloth_fit.h"
#include "fitting/thread_fit.h"
#include "models/presets.h"

namespace clothfit {
namespace {

template <typename Options>
Options Paper() {
  Options o;
  o.energy_bound = false;
  return o;
}

MeasurementTable Table(const ModelParams& truth, int rows) {
  DirectionSampling sampling;
  sampling.rows = rows;
  SynthOptions synth;
  synth.noise = 0.02;
  return SyntheticTable(truth, sampling, synth, 11);
}

void BM_ThreadFit(benchmark::State& state) {
  ThreadParams truth;  // the flat polyester thread of the satin
  truth.eta = 1.539;
  truth.kd = 0.1;
  truth.gamma_s_deg = 2.5;
  truth.gamma_v_deg = 5.0;
  truth.albedo = glm::dvec3(0.035, 0.01295, 0.0105);
  const MeasurementTable table = Table(truth, static_cast<int>(state.range(0)));
  for (auto _ : state) {
    const ThreadFitResult r = FitThread(table, Paper<ThreadFitOptions>());
    if (!r.report.converged) state.SkipWithError("fit did not converge");
    benchmark::DoNotOptimize(r.params.eta);
  }
}
BENCHMARK(BM_ThreadFit)->Arg(10000)->Unit(benchmark::kMillisecond);

void BM_ClothFit(benchmark::State& state, const char* preset) {
  ClothParams truth;
  GetPreset(preset, &truth);
  const MeasurementTable table = Table(truth, static_cast<int>(state.range(0)));
  const ClothParams start = GenericClothStart(truth);
  for (auto _ : state) {
    const ClothFitResult r = FitCloth(table, start, Paper<ClothFitOptions>());
    if (!r.report.converged) state.SkipWithError("fit did not converge");
    benchmark::DoNotOptimize(r.params.threads[0].params.kd);
  }
}
BENCHMARK_CAPTURE(BM_ClothFit, satin, "polyester_satin_charmeuse")
    ->Arg(5000)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ClothFit, linen, "linen_plain")
    ->Arg(5000)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ClothFit, silk_crepe, "silk_crepe_de_chine")
    ->Arg(5000)
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace clothfit

BENCHMARK_MAIN();
