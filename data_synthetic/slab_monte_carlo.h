// Monte Carlo ground truth for the slab of docs/models.md: the same
// plane-parallel layer (optical thickness tau, single-scattering albedo A,
// isotropic scattering) with every order of scattering, lit by collimated
// beams.
//
// Method (per beam; docs/slab.md has the derivation):
//  - Photons start at the lit face with weight 1 per channel (unit
//    irradiance on the face; N photons carry 1/N each).
//  - Every flight is forced to collide inside the slab: the weight is
//    multiplied by the probability 1 - exp(-d) of a collision before the
//    boundary (d: optical distance to it along the flight) and the collision
//    point is drawn from the exponential truncated to [0, d). The part
//    exp(-d) leaves the slab: for the first flight that is the direct
//    transmittance; after a scattering it is tallied as escaped energy
//    (total diffuse reflectance / transmittance and a histogram in |mu|).
//  - At each collision (depth t, weight W before it) next-event estimation
//    scores the radiance leaving in every view direction mu_o:
//      top:    W A / (4 pi) exp(-t / mu_o) / mu_o            (reflection)
//      bottom: W A / (4 pi) exp(-(tau - t) / mu_o) / mu_o    (transmission)
//    which is an unbiased estimate of f_r, f_t per unit irradiance at exactly
//    those directions (no angular binning). The weight becomes W A, a new
//    direction is drawn uniformly on the sphere (isotropic scattering).
//  - Russian roulette ends a walk whose largest channel weight falls below
//    1e-3 (survival 1/10, weight x 10), so the estimate stays unbiased.
//  - Channels share the random walk when they share tau (albedo only scales
//    the weights, A^k after k scatterings); channels with another tau get a
//    walk of their own.
// Isotropic scattering makes the scattered light independent of azimuth, so
// views are given by their polar angle alone.
//
// Statistical errors: photons are independent, so each output's standard
// error is the sample standard deviation of the per-photon scores over
// sqrt(N). The direct transmittance is estimated separately by an analog
// test on the same photons (free path > tau/mu_i), with binomial error.
// Photons are processed in fixed chunks, each seeded from (seed, channel
// group, beam, chunk), and summed in chunk order: results are identical for
// any number of threads.
#pragma once

#include <cstdint>
#include <vector>

#include "data_synthetic/synthetic_table.h"
#include "io/table.h"
#include "models/slab.h"

namespace clothfit {

struct SlabMonteCarloOptions {
  SlabParams params;
  // Polar angles of the incident beams, degrees in [0, 89].
  std::vector<double> theta_i_deg = {0.0, 15.0, 30.0, 45.0, 60.0, 75.0};
  // Polar angles of the views, degrees in [0, 89]: reflection at theta_o
  // (wo.z > 0), transmission at 180 - theta_o (wo.z < 0).
  std::vector<double> theta_o_deg = {0.0,  10.0, 20.0, 30.0, 40.0,
                                     50.0, 60.0, 70.0, 80.0};
  int64_t photons = 100000;  // per beam, [1, 1e10]
  uint64_t seed = 1;
  // Highest scattering order scored: 0 = all (the ground truth); 1 = single
  // scattering only, which is what docs/models.md's formulas describe.
  int max_order = 0;
  int histogram_bins = 10;  // escape histogram, uniform in |mu|, [1, 1000]
  int threads = 0;          // 0 = std::thread::hardware_concurrency()
};

// A per-channel estimate and its standard error.
struct McEstimate {
  glm::dvec3 mean{0.0};
  glm::dvec3 std_error{0.0};
};

struct SlabMonteCarloBeam {
  double theta_i_deg = 0.0;
  std::vector<McEstimate> reflection;    // f_r (1/sr) per theta_o_deg
  std::vector<McEstimate> transmission;  // f_t (1/sr) per theta_o_deg
  McEstimate direct;                     // direct transmittance D(mu_i)
  // Energy fractions of the unit irradiance: scattered light leaving
  // through the lit face (reflected) or the far face (diffusely
  // transmitted); the rest of 1 - direct is absorbed.
  McEstimate reflected, transmitted;
  // The same split by |mu| of the escaping direction: bin k holds
  // |mu| in [k, k+1) / histogram_bins.
  std::vector<McEstimate> reflected_histogram, transmitted_histogram;
};

struct SlabMonteCarloResult {
  SlabMonteCarloOptions options;
  std::vector<SlabMonteCarloBeam> beams;  // one per theta_i_deg
  double seconds = 0.0;
};

// Runs the simulation. Throws InputError (naming the option) for invalid
// parameters or options.
SlabMonteCarloResult RunSlabMonteCarlo(const SlabMonteCarloOptions& options);

// The direction rows of a BSDF table for beams at theta_i_deg (phi_i = 0)
// and views at theta_o_deg (phi_o = 0): per beam, the reflection rows in
// theta_o order, then the transmission rows (theta = 180 - theta_o).
std::vector<TableRow> SlabBsdfRows(const std::vector<double>& theta_i_deg,
                                   const std::vector<double>& theta_o_deg);
// The rows of a direct-transmittance table: one view per beam, looking back
// along it from the far side (wo = -wi).
std::vector<TableRow> SlabTransmittanceRows(
    const std::vector<double>& theta_i_deg);

// A BSDF table (rows as SlabBsdfRows) and a direct-transmittance table
// (rows as SlabTransmittanceRows; one channel when tau is scalar).
struct SlabTables {
  MeasurementTable bsdf;
  MeasurementTable transmittance;
};

// The single-scattering formulas' tables at the Monte Carlo's directions,
// with SynthesizeValues' noise (synth.quantity for the BSDF table).
SlabTables SlabModelTables(const SlabParams& params,
                           const std::vector<double>& theta_i_deg,
                           const std::vector<double>& theta_o_deg,
                           const SynthOptions& synth, Random* random);

// The simulation as docs/formats.md tables, r,g,b with sigma_r,g,b = standard
// error (floored at 1e-12, as synthetic tables, where a score had no
// variance). Quantity brdf
// or cosine_weighted (f |wi.z|); rows as SlabBsdfRows. Metadata: sample,
// model, tau, albedo, photons, seed, max_order and per beam the energy
// split ("energy_theta_i_<deg>").
MeasurementTable SlabMonteCarloBsdfTable(const SlabMonteCarloResult& result,
                                         Quantity quantity);
// Quantity transmittance, columns theta_o,phi_o and value (one channel when
// tau is scalar) or r,g,b, with sigma; rows as SlabTransmittanceRows.
MeasurementTable SlabMonteCarloTransmittanceTable(
    const SlabMonteCarloResult& result);

}  // namespace clothfit
