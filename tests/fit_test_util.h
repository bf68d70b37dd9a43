// Helpers shared by the fit tests.
#pragma once

#include <algorithm>
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include "data_synthetic/synthetic_table.h"

namespace clothfit {
namespace testing_util {

// A synthetic table of `rows` random direction pairs with multiplicative
// noise (and sigma when noise > 0).
inline MeasurementTable NoisyTable(const ModelParams& truth, double noise,
                                   uint64_t seed, int rows) {
  DirectionSampling sampling;
  sampling.rows = rows;
  SynthOptions synth;
  synth.noise = noise;
  return SyntheticTable(truth, sampling, synth, seed);
}

// The names listed by FitReport::identifiability ("not identifiable: a, b").
inline std::vector<std::string> UndeterminedNames(const std::string& text) {
  std::vector<std::string> names;
  const size_t colon = text.find(':');
  if (colon == std::string::npos) return names;
  std::stringstream list(text.substr(colon + 1));
  std::string name;
  while (std::getline(list, name, ',')) {
    const size_t b = name.find_first_not_of(' ');
    if (b != std::string::npos) names.push_back(name.substr(b));
  }
  return names;
}

inline bool Contains(const std::vector<std::string>& names,
                     const std::string& n) {
  return std::find(names.begin(), names.end(), n) != names.end();
}

}  // namespace testing_util
}  // namespace clothfit
