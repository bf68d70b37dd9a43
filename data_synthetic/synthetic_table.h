// Synthetic measurement tables: direction sets over the hemisphere and
// model values with deterministic multiplicative noise. Used by
// `clothfit synth`, the tests and the benchmarks.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "io/table.h"
#include "models/evaluate.h"

namespace clothfit {

// Deterministic random numbers, identical on every platform (SplitMix64 for
// the seed, xoshiro256** for the stream, Box-Muller for normals).
class Random {
 public:
  explicit Random(uint64_t seed);
  uint64_t NextU64();
  double Uniform();  // [0, 1)
  double Normal();   // mean 0, standard deviation 1

 private:
  uint64_t s_[4];
  bool has_spare_ = false;
  double spare_ = 0.0;
};

struct DirectionSampling {
  int rows = 2000;
  // Cosine of the largest polar angle sampled (0 reaches grazing; the
  // sampler also places rows at theta = 89.9 deg when grazing is included).
  double min_cos_theta = 0.0;
  // wo over the whole sphere instead of the upper hemisphere (thread and
  // slab tables).
  bool full_sphere_out = false;
};

// Whether a model's tables sample wo over the whole sphere: a thread (its
// thread frame has no surface) and a slab (transmission); the others are
// reflection only.
bool FullSphereOut(const ModelParams& params);

// Rows uniform in solid angle over the hemisphere (wi, and wo unless
// full_sphere_out), with 5 % of the rows at grazing (theta = 89.9 deg)
// when min_cos_theta == 0. Values are zero; sigma and weight are 1.
std::vector<TableRow> SampleDirections(const DirectionSampling& sampling,
                                       Random* random);

struct SynthOptions {
  Quantity quantity = Quantity::kBrdf;
  // Relative standard deviation of multiplicative Gaussian noise; 0 = none.
  double noise = 0.0;
};

// Multiplicative Gaussian noise on a table's values: each channel below
// table->channels is multiplied by 1 + noise N(0, 1) (the others copy
// channel 0), and sigma = max(noise max(|value|, value_floor), 1e-12) from
// the clean value, value_floor per channel (it keeps a finite weight where
// the clean value is 0, e.g. 0.01 of a transmittance's full scale);
// has_sigma. noise > 0.
void AddMultiplicativeNoise(double noise, const glm::dvec3& value_floor,
                            Random* random, MeasurementTable* table);

// Fills the rows' values with the model's and adds noise. When noise > 0
// the rows get sigma = noise * max(|clean value|, floor), the floor that of
// the fits' default relative noise (RelativeNoiseFloor, io/table.h), and
// the table has_sigma. Negative noisy values are kept (a measurement can be).
void SynthesizeValues(const ModelParams& params, const SynthOptions& options,
                      Random* random, MeasurementTable* table);

// Both in one call, from a seed: `sampling.rows` random direction pairs
// (wo over the whole sphere for a thread or slab model) and the model's
// values.
MeasurementTable SyntheticTable(const ModelParams& params,
                                DirectionSampling sampling,
                                const SynthOptions& options, uint64_t seed);

}  // namespace clothfit
