#include "data_synthetic/slab_error_map.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "data_synthetic/slab_monte_carlo.h"
#include "io/input_error.h"
#include "io/text_util.h"
#include "models/evaluate.h"

namespace clothfit {
SlabErrorMap ComputeSlabErrorMap(const SlabErrorMapOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  if (options.taus.empty() || options.albedos.empty()) {
    throw InputError("slab error map: needs at least one tau and one albedo");
  }
  SlabErrorMap map;
  map.options = options;
  const size_t n_tau = options.taus.size();
  map.cells.resize(options.albedos.size() * n_tau);
  for (size_t t = 0; t < n_tau; ++t) {
    // Three albedos per simulation, as the three channels of one walk.
    for (size_t a0 = 0; a0 < options.albedos.size(); a0 += 3) {
      SlabMonteCarloOptions mc;
      mc.params.tau = glm::dvec3(options.taus[t]);
      for (int c = 0; c < 3; ++c) {
        mc.params.albedo[c] =
            options.albedos[std::min(a0 + c, options.albedos.size() - 1)];
      }
      mc.theta_i_deg = options.theta_i_deg;
      mc.theta_o_deg = options.theta_o_deg;
      mc.photons = options.photons;
      mc.seed = options.seed;
      mc.threads = options.threads;
      const SlabMonteCarloResult result = RunSlabMonteCarlo(mc);
      const MeasurementTable table =
          SlabMonteCarloBsdfTable(result, Quantity::kBrdf);
      glm::dvec3 se(0.0), ss(0.0), noise(0.0), worst(0.0);
      for (const TableRow& row : table.rows) {
        const glm::dvec3 model =
            Value(mc.params, row.wi, row.wo, Quantity::kBrdf);
        const glm::dvec3 d = model - row.value;
        se += d * d;
        ss += row.value * row.value;
        noise += row.sigma * row.sigma;
        for (int c = 0; c < 3; ++c) {
          if (row.value[c] > 0.0) {
            worst[c] = std::max(worst[c], std::abs(d[c]) / row.value[c]);
          }
        }
      }
      for (int c = 0; c < 3 && a0 + c < options.albedos.size(); ++c) {
        SlabErrorCell& cell = map.cells[(a0 + c) * n_tau + t];
        cell.tau = options.taus[t];
        cell.albedo = options.albedos[a0 + c];
        cell.relative_rms_error = ss[c] > 0.0 ? std::sqrt(se[c] / ss[c]) : 0.0;
        cell.max_relative_error = worst[c];
        cell.relative_noise = ss[c] > 0.0 ? std::sqrt(noise[c] / ss[c]) : 0.0;
        cell.estimated_error = SlabSingleScatterError(cell.tau, cell.albedo);
      }
    }
  }
  map.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0)
          .count();
  return map;
}

std::string SlabErrorMapCsv(const SlabErrorMap& map) {
  const SlabErrorMapOptions& o = map.options;
  std::string out =
      "# single-scattering slab (docs/models.md) against Monte Carlo, all "
      "orders; " +
      std::to_string(o.photons) + " photons per beam, seed " +
      std::to_string(o.seed) + "\n" +
      "tau,albedo,relative_rms_error,max_relative_error,relative_noise,"
      "estimated_error\n";
  for (const SlabErrorCell& cell : map.cells) {
    const double values[] = {cell.tau,
                             cell.albedo,
                             cell.relative_rms_error,
                             cell.max_relative_error,
                             cell.relative_noise,
                             cell.estimated_error};
    for (size_t k = 0; k < 6; ++k) {
      out += (k ? "," : "") + text_util::FormatNumber(values[k]);
    }
    out += "\n";
  }
  return out;
}

}  // namespace clothfit
