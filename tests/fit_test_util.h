// Helpers shared by the fit tests.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include "data_synthetic/synthetic_table.h"
#include "fitting/cloth_fit.h"
#include "fitting/fit_result.h"
#include "fitting/thread_fit.h"
#include "models/bounded.h"
#include "models/evaluate.h"
#include "models/lafortune.h"

namespace clothfit {
namespace testing_util {

// The reported parameter `name` (a test failure when there is none).
inline const ParameterReport& Param(const FitReport& report,
                                    const std::string& name) {
  for (const ParameterReport& p : report.parameters) {
    if (p.name == name) return p;
  }
  ADD_FAILURE() << "no parameter " << name;
  static const ParameterReport kNone;
  return kNone;
}

// Thread or cloth fit options that fit the paper's model (Sadeghi et al.
// 2013) instead of the default bounded one: for tables drawn from the
// paper's model (a NoisyTable of parameters without a bound), whose rows
// toward grazing the bounded model does not reproduce.
template <typename Options>
Options PaperModel() {
  Options o;
  o.energy_bound = false;
  return o;
}

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

// The sum of squares over the table's rows of the paper's model at
// `paper` bounded by its own bound, found afresh (models/bounded.h); with
// `by_sigma`, of the residuals divided by the rows' sigma (the cost a fit
// with the table's noise model minimises).
inline double BoundedSquares(const ModelParams& paper,
                             const MeasurementTable& table,
                             bool by_sigma = false) {
  const ModelParams bounded = WithEnergyBound(paper);
  double sum = 0.0;
  for (const TableRow& row : table.rows) {
    glm::dvec3 d =
        Evaluate(bounded, row.wi, row.wo, table.quantity) - row.value;
    if (by_sigma) d /= row.sigma;
    for (int c = 0; c < table.channels; ++c) sum += d[c] * d[c];
  }
  return sum;
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

// n x n hemisphere directions, uniform in (cos theta, phi) strata.
inline std::vector<glm::dvec3> Hemisphere(int n, double phase = 0.0) {
  std::vector<glm::dvec3> out;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const double ct = (i + 0.5) / n;
      const double st = std::sqrt(1.0 - ct * ct);
      const double phi = 2.0 * kPi * (j + 0.5 + phase) / n;
      out.push_back({st * std::cos(phi), st * std::sin(phi), ct});
    }
  }
  return out;
}

// A cosine-weighted table of a Lafortune model, noise-free: every light
// for each view (view-major).
inline MeasurementTable LafortuneTable(const LafortuneModel& m,
                                       const std::vector<glm::dvec3>& lights,
                                       const std::vector<glm::dvec3>& views) {
  MeasurementTable t;
  t.quantity = Quantity::kCosineWeighted;
  for (const glm::dvec3& v : views) {
    for (const glm::dvec3& l : lights) {
      TableRow r;
      r.wi = l;
      r.wo = v;
      r.value = LafortuneRho(m, l, v);
      t.rows.push_back(r);
    }
  }
  return t;
}

}  // namespace testing_util
}  // namespace clothfit
