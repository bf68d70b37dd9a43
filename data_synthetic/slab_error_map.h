// Where the single-scattering slab fails: the error of docs/models.md's
// formulas against Monte Carlo ground truth (all orders of scattering) over a
// grid of optical thickness x albedo, written as a PNG heat map (OpenCV) and
// the CSV behind it.
//
// Per grid cell (tau, A), with the Monte Carlo f_r, f_t at the beams and
// views of the options (data_synthetic/slab_monte_carlo.h):
//   relative rms error = sqrt(sum (model - mc)^2 / sum mc^2)  over all rows
//   max relative error = max |model - mc| / mc                over all rows
//   relative noise     = sqrt(sum se^2 / sum mc^2)   (the truth's own error)
//   estimated error    = A q(tau), models/slab.h's closed-form estimate
// An error near the noise is not resolved; the CSV keeps both. Albedos share
// the random walks of their tau (three per simulation, as channels).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace clothfit {

struct SlabErrorMapOptions {
  std::vector<double> taus = {0.001, 0.003, 0.01, 0.03, 0.1,
                              0.2,   0.5,   1.0,  2.0,  5.0};
  std::vector<double> albedos = {0.05, 0.1, 0.2, 0.4, 0.6, 0.8, 0.9, 1.0};
  std::vector<double> theta_i_deg = {0.0, 30.0, 60.0};
  std::vector<double> theta_o_deg = {0.0,  10.0, 20.0, 30.0, 40.0,
                                     50.0, 60.0, 70.0, 80.0};
  int64_t photons = 20000;  // per beam and tau
  uint64_t seed = 1;
  int threads = 0;  // 0 = all cores
};

struct SlabErrorCell {
  double tau = 0.0, albedo = 0.0;
  double relative_rms_error = 0.0;
  double max_relative_error = 0.0;
  double relative_noise = 0.0;
  double estimated_error = 0.0;
};

struct SlabErrorMap {
  SlabErrorMapOptions options;
  std::vector<SlabErrorCell> cells;  // albedo-major: cells[a * taus + t]
  double seconds = 0.0;
};

// Runs the simulations. Throws InputError for taus or albedos outside the
// model's range, empty lists, or invalid Monte Carlo options.
SlabErrorMap ComputeSlabErrorMap(const SlabErrorMapOptions& options);

// CSV: a '#' comment line, then tau,albedo,relative_rms_error,
// max_relative_error,relative_noise,estimated_error, one row per cell.
std::string SlabErrorMapCsv(const SlabErrorMap& map);

}  // namespace clothfit
