#include "data_synthetic/synthetic_table.h"

#include <algorithm>
#include <cmath>

namespace clothfit {
namespace {

uint64_t SplitMix64(uint64_t* x) {
  uint64_t z = (*x += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

uint64_t Rotl(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }

// Uniform in solid angle over the part of the hemisphere with
// cos(theta) >= min_cos; `sign` = -1 mirrors it below the surface.
glm::dvec3 SampleHemisphere(double min_cos, double sign, Random* random) {
  const double z = min_cos + (1.0 - min_cos) * (1.0 - random->Uniform());
  const double phi = 2.0 * kPi * random->Uniform();
  const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
  return glm::dvec3(r * std::cos(phi), r * std::sin(phi), sign * z);
}

glm::dvec3 Grazing(Random* random) {
  constexpr double kTheta = Radians(89.9);
  const double phi = 2.0 * kPi * random->Uniform();
  return glm::dvec3(std::sin(kTheta) * std::cos(phi),
                    std::sin(kTheta) * std::sin(phi), std::cos(kTheta));
}

}  // namespace

Random::Random(uint64_t seed) {
  for (uint64_t& s : s_) s = SplitMix64(&seed);
}

uint64_t Random::NextU64() {
  const uint64_t result = Rotl(s_[1] * 5, 7) * 9;
  const uint64_t t = s_[1] << 17;
  s_[2] ^= s_[0];
  s_[3] ^= s_[1];
  s_[1] ^= s_[2];
  s_[0] ^= s_[3];
  s_[2] ^= t;
  s_[3] = Rotl(s_[3], 45);
  return result;
}

double Random::Uniform() {
  return static_cast<double>(NextU64() >> 11) * 0x1.0p-53;
}

double Random::Normal() {
  if (has_spare_) {
    has_spare_ = false;
    return spare_;
  }
  const double u1 = 1.0 - Uniform();  // (0, 1]
  const double u2 = Uniform();
  const double r = std::sqrt(-2.0 * std::log(u1));
  spare_ = r * std::sin(2.0 * kPi * u2);
  has_spare_ = true;
  return r * std::cos(2.0 * kPi * u2);
}

std::vector<TableRow> SampleDirections(const DirectionSampling& sampling,
                                       Random* random) {
  std::vector<TableRow> rows(std::max(0, sampling.rows));
  const bool grazing = sampling.min_cos_theta <= 0.0;
  for (size_t i = 0; i < rows.size(); ++i) {
    TableRow& row = rows[i];
    // Every 20th row puts the light or the viewer at grazing.
    const bool graze = grazing && i % 20 == 19;
    row.wi = graze && i % 40 == 19
                 ? Grazing(random)
                 : SampleHemisphere(sampling.min_cos_theta, 1.0, random);
    if (graze && i % 40 == 39) {
      row.wo = Grazing(random);
    } else if (sampling.full_sphere_out) {
      row.wo =
          SampleHemisphere(0.0, random->Uniform() < 0.5 ? -1.0 : 1.0, random);
    } else {
      row.wo = SampleHemisphere(sampling.min_cos_theta, 1.0, random);
    }
  }
  return rows;
}

bool FullSphereOut(const ModelParams& params) {
  return std::holds_alternative<ThreadParams>(params) ||
         std::holds_alternative<SlabParams>(params);
}

void SynthesizeValues(const ModelParams& params, const SynthOptions& options,
                      Random* random, MeasurementTable* table) {
  table->quantity = options.quantity;
  table->has_sigma = false;
  for (TableRow& row : table->rows) {
    row.value = Evaluate(params, row.wi, row.wo, options.quantity);
    row.sigma = glm::dvec3(1.0);
  }
  if (options.noise > 0.0) {
    // The floor of the fits' default relative noise model (io/table.h): a
    // value of 0 (the bounded model at the horizon) gets a finite sigma.
    glm::dvec3 floor(0.0);
    std::vector<double> values(table->rows.size());
    for (int c = 0; c < 3; ++c) {
      for (size_t i = 0; i < values.size(); ++i) {
        values[i] = std::abs(table->rows[i].value[c]);
      }
      floor[c] = RelativeNoiseFloor(values);
    }
    AddMultiplicativeNoise(options.noise, floor, random, table);
  }
}

void AddMultiplicativeNoise(double noise, const glm::dvec3& value_floor,
                            Random* random, MeasurementTable* table) {
  table->has_sigma = true;
  for (TableRow& row : table->rows) {
    for (int c = 0; c < 3; ++c) {
      if (c >= table->channels) {
        row.value[c] = row.value[0];
        row.sigma[c] = row.sigma[0];
        continue;
      }
      const double clean = row.value[c];
      row.sigma[c] =
          std::max(noise * std::max(std::abs(clean), value_floor[c]), 1e-12);
      row.value[c] = clean * (1.0 + noise * random->Normal());
    }
  }
}

MeasurementTable SyntheticTable(const ModelParams& params,
                                DirectionSampling sampling,
                                const SynthOptions& options, uint64_t seed) {
  Random random(seed);
  sampling.full_sphere_out = FullSphereOut(params);
  MeasurementTable table;
  table.rows = SampleDirections(sampling, &random);
  SynthesizeValues(params, options, &random, &table);
  return table;
}

}  // namespace clothfit
