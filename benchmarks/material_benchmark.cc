// Speed of the renderer's inner loop: Material::F on a preset, a
// Lafortune file and a parameter mip map, the cloth sampler, and one
// preview render. Medians and spread:
//   build/benchmarks/material_benchmark --benchmark_repetitions=10
//     --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "api/material.h"
#include "models/cloth_sampling.h"
#include "models/presets.h"
#include "render/preview.h"

namespace clothfit {
namespace {

// Unit directions above the surface, uniform in solid angle.
std::vector<glm::dvec3> Hemisphere(int n) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<glm::dvec3> out;
  for (int i = 0; i < n; ++i) {
    const double z = u(rng), phi = 2.0 * kPi * u(rng);
    const double r = std::sqrt(1.0 - z * z);
    out.emplace_back(r * std::cos(phi), r * std::sin(phi), z);
  }
  return out;
}

ClothParams Satin() {
  ClothParams c;
  GetPreset("polyester_satin_charmeuse", &c);
  return c;
}

// F of a material at 4096 x 4096 pairs of hemisphere directions, in the
// material's scalar type (Material: double, MaterialF: float).
template <typename M>
void RunF(benchmark::State& state, const M& m) {
  using Vec = typename M::Vec;
  std::vector<Vec> dirs;
  for (const glm::dvec3& d : Hemisphere(4096)) dirs.push_back(Vec(d));
  size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(
        m.F(dirs[i & 4095], dirs[(i * 7 + 3) & 4095], 0.3f, 0.6f, 0));
    ++i;
  }
  state.SetItemsProcessed(state.iterations());
}

LafortuneModel TwoLobes() {
  LafortuneModel m;
  m.params.lobes = {LafortuneLobe(), LafortuneLobe()};
  m.params.lobes[1].n = glm::dvec3(3.0);
  return m;
}

// Two lobes whose channels differ (an rgb texel): a power per channel.
LafortuneModel TwoRgbLobes() {
  LafortuneModel m = TwoLobes();
  m.params.lobes[0].cx = glm::dvec3(-0.9, -0.8, -0.7);
  m.params.lobes[1].n = glm::dvec3(3.0, 4.0, 5.0);
  return m;
}

void BM_MaterialF_SatinPreset(benchmark::State& state) {
  RunF(state, Material::FromParams(Satin()));
}
BENCHMARK(BM_MaterialF_SatinPreset);

void BM_MaterialF_SatinPreset_Float(benchmark::State& state) {
  RunF(state, MaterialF::FromParams(Satin()));
}
BENCHMARK(BM_MaterialF_SatinPreset_Float);

void BM_MaterialF_Lafortune2Lobes(benchmark::State& state) {
  RunF(state, Material::FromParams(TwoLobes()));
}
BENCHMARK(BM_MaterialF_Lafortune2Lobes);

void BM_MaterialF_Lafortune2Lobes_Float(benchmark::State& state) {
  RunF(state, MaterialF::FromParams(TwoLobes()));
}
BENCHMARK(BM_MaterialF_Lafortune2Lobes_Float);

void BM_MaterialF_Lafortune2RgbLobes(benchmark::State& state) {
  RunF(state, Material::FromParams(TwoRgbLobes()));
}
BENCHMARK(BM_MaterialF_Lafortune2RgbLobes);

void BM_MaterialF_Lafortune2RgbLobes_Float(benchmark::State& state) {
  RunF(state, MaterialF::FromParams(TwoRgbLobes()));
}
BENCHMARK(BM_MaterialF_Lafortune2RgbLobes_Float);

void BM_SampleClothWi_Satin(benchmark::State& state) {
  const ClothParams satin = Satin();
  const glm::dvec3 wo = glm::normalize(glm::dvec3(0.5, 0.2, 0.8));
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (auto _ : state) {
    benchmark::DoNotOptimize(SampleClothWi(satin, wo, u(rng), u(rng)));
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_SampleClothWi_Satin);

void BM_RenderCylinders_Satin96(benchmark::State& state) {
  const ClothParams satin = Satin();
  for (auto _ : state) {
    benchmark::DoNotOptimize(RenderCylinders(satin, PreviewOptions()));
  }
}
BENCHMARK(BM_RenderCylinders_Satin96)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace clothfit

BENCHMARK_MAIN();
