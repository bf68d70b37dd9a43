// Model evaluation speed (the target: >= 1 million satin rho evaluations
// per second on one core). Run with --benchmark_repetitions=10 for medians and
// spread: build/benchmarks/model_benchmark --benchmark_repetitions=10
#include <benchmark/benchmark.h>

#include <vector>

#include "data_synthetic/synthetic_table.h"
#include "models/presets.h"

namespace clothfit {
namespace {

std::vector<TableRow> Directions(bool full_sphere) {
  Random random(7);
  DirectionSampling sampling;
  sampling.rows = 4096;
  sampling.full_sphere_out = full_sphere;
  return SampleDirections(sampling, &random);
}

void BM_ClothRho(benchmark::State& state, const char* preset) {
  ClothParams cloth;
  GetPreset(preset, &cloth);
  const std::vector<TableRow> rows = Directions(false);
  size_t i = 0;
  for (auto _ : state) {
    const TableRow& r = rows[i++ & 4095];
    benchmark::DoNotOptimize(ClothRho(cloth, r.wi, r.wo));
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK_CAPTURE(BM_ClothRho, satin, "polyester_satin_charmeuse");
BENCHMARK_CAPTURE(BM_ClothRho, linen, "linen_plain");
BENCHMARK_CAPTURE(BM_ClothRho, velvet, "velvet");

void BM_ThreadBsdf(benchmark::State& state) {
  const ThreadParams thread;
  const std::vector<TableRow> rows = Directions(true);
  size_t i = 0;
  for (auto _ : state) {
    const TableRow& r = rows[i++ & 4095];
    benchmark::DoNotOptimize(ThreadBsdfLocal(thread, r.wi, r.wo));
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_ThreadBsdf);

// The slab's f_r or f_t, wo over the whole sphere.
void BM_SlabBsdf(benchmark::State& state) {
  SlabParams slab;
  slab.tau = glm::dvec3(0.08);
  slab.albedo = {0.9, 0.6, 0.3};
  const std::vector<TableRow> rows = Directions(true);
  size_t i = 0;
  for (auto _ : state) {
    const TableRow& r = rows[i++ & 4095];
    benchmark::DoNotOptimize(SlabBsdf(slab, r.wi, r.wo));
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_SlabBsdf);

}  // namespace
}  // namespace clothfit

BENCHMARK_MAIN();
