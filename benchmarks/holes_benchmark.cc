// Speed of semi-transparent textures with thickness: counts and
// the full pyramid of a 4096 x 4096 mask in under 1 s; Algorithm 3.1 at
// >= 50 million evaluations per second per core. Run with repetitions for
// medians and spread:
//   build/benchmarks/holes_benchmark --benchmark_repetitions=10
#include <benchmark/benchmark.h>

#include <vector>

#include "data_synthetic/holes_truth.h"
#include "data_synthetic/synthetic_table.h"
#include "holes/hole_texture.h"

namespace clothfit {
namespace {

constexpr int kTable = 4096;  // texels and offsets cycled through

// A pyramid from a side x side random mask: the nine counts (the speed
// target: a 4096 x 4096 mask) or the extension's run counts.
void BM_Pyramid(benchmark::State& state, CountPyramid (*build)(const Mask&),
                int side) {
  const Mask mask = RandomMask(side, side, 0.4, 1);
  for (auto _ : state) {
    const CountPyramid pyramid = build(mask);
    double top[kDistanceChannels];
    pyramid.Counts(pyramid.levels() - 1, 0, 0, top);
    benchmark::DoNotOptimize(top);
  }
  state.SetItemsProcessed(state.iterations() * side * side);
}
BENCHMARK_CAPTURE(BM_Pyramid, counts_4096, HoleCountsFromMask, 4096)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Pyramid, distances_1024, HoleDistancesFromMask, 1024)
    ->Unit(benchmark::kMillisecond);

// Texels of every level of a 256 x 256 pyramid and offsets with |rx|,
// |ry| < 1.5 (the clamp is part of the work).
struct Inputs {
  HoleTexture texture;
  std::vector<HoleTexel> texels;
  std::vector<HoleDistanceTexel> distances;
  std::vector<glm::dvec2> offsets;
};

const Inputs& GetInputs() {
  static const Inputs* inputs = [] {
    auto* in = new Inputs;
    in->texture = AnalyzeMask(RandomMask(256, 256, 0.4, 2), true);
    Random random(3);
    const CountPyramid& counts = in->texture.counts;
    for (int i = 0; i < kTable; ++i) {
      const int level = static_cast<int>(random.Uniform() * counts.levels());
      const int x = static_cast<int>(random.Uniform() * counts.width(level));
      const int y = static_cast<int>(random.Uniform() * counts.height(level));
      in->texels.push_back(HoleTexelAt(counts, level, x, y));
      in->distances.push_back(
          DistanceTexelAt(in->texture.distances, level, x, y));
      in->offsets.emplace_back(3.0 * random.Uniform() - 1.5,
                               3.0 * random.Uniform() - 1.5);
    }
    return in;
  }();
  return *inputs;
}

void BM_Algorithm31(benchmark::State& state) {
  const Inputs& in = GetInputs();
  size_t i = 0;
  for (auto _ : state) {
    const size_t k = i++ & (kTable - 1);
    benchmark::DoNotOptimize(
        Algorithm31(in.texels[k], in.offsets[(k * 7) & (kTable - 1)]));
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_Algorithm31);

// With the texel fetched from the pyramid (uint8 / int32 -> double).
void BM_Algorithm31FromPyramid(benchmark::State& state) {
  const Inputs& in = GetInputs();
  const HoleTexture& texture = in.texture;
  const int level = static_cast<int>(state.range(0));
  const int w = texture.counts.width(level), h = texture.counts.height(level);
  size_t i = 0;
  for (auto _ : state) {
    const size_t k = i++;
    const int x = static_cast<int>(k % w), y = static_cast<int>((k / w) % h);
    benchmark::DoNotOptimize(EvaluateTexel(texture, HoleMethod::kAlgorithm31,
                                           level, x, y,
                                           in.offsets[k & (kTable - 1)]));
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_Algorithm31FromPyramid)->Arg(0)->Arg(3);

void BM_Extension(benchmark::State& state) {
  const Inputs& in = GetInputs();
  size_t i = 0;
  for (auto _ : state) {
    const size_t k = i++ & (kTable - 1);
    benchmark::DoNotOptimize(
        ExtendedRatios(in.texels[k], in.distances[k],
                       in.offsets[(k * 7) & (kTable - 1)] * 3.0));
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_Extension);

// Ground-truth rays (2D DDA) through a 256 x 256 random mask, |r| ~ 2.
void BM_TruthRays(benchmark::State& state) {
  const Mask mask = RandomMask(256, 256, 0.4, 4);
  const Footprint tile = TileFootprint(mask, 1 << 16);
  for (auto _ : state) {
    benchmark::DoNotOptimize(HoleTruth(mask, {1.7, -1.1}, tile));
  }
  state.SetItemsProcessed(state.iterations() * tile.samples_u * tile.samples_v);
}
BENCHMARK(BM_TruthRays)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace clothfit

BENCHMARK_MAIN();
