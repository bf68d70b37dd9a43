#include "data_synthetic/slab_error_map.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "charts/heat_map.h"
#include "data_synthetic/slab_monte_carlo.h"
#include "io/atomic_file.h"
#include "io/input_error.h"
#include "models/evaluate.h"

namespace clothfit {
namespace {

std::string Short(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%g", value);
  return text;
}

}  // namespace

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
            SlabValue(mc.params, row.wi, row.wo, Quantity::kBrdf);
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
      "# single-scattering slab (SPEC 3.4) against Monte Carlo, all orders; " +
      std::to_string(o.photons) + " photons per beam, seed " +
      std::to_string(o.seed) + "\n" +
      "tau,albedo,relative_rms_error,max_relative_error,relative_noise,"
      "estimated_error\n";
  for (const SlabErrorCell& cell : map.cells) {
    char line[200];
    std::snprintf(line, sizeof(line), "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n",
                  cell.tau, cell.albedo, cell.relative_rms_error,
                  cell.max_relative_error, cell.relative_noise,
                  cell.estimated_error);
    out += line;
  }
  return out;
}

void WriteSlabErrorMap(const SlabErrorMap& map, const std::string& png_path,
                       const std::string& csv_path) {
  const SlabErrorMapOptions& o = map.options;
  HeatMap chart;
  chart.title =
      "single-scattering slab vs Monte Carlo: relative rms error of f_r, f_t";
  chart.x_title = "optical thickness tau";
  chart.y_title = "albedo A";
  for (double tau : o.taus) chart.x_labels.push_back(Short(tau));
  const size_t n_tau = o.taus.size();
  HeatMapPanel panel;
  for (size_t a = o.albedos.size(); a-- > 0;) {  // highest albedo on top
    chart.y_labels.push_back(Short(o.albedos[a]));
    for (size_t t = 0; t < n_tau; ++t) {
      const SlabErrorCell& cell = map.cells[a * n_tau + t];
      panel.values.push_back(cell.relative_rms_error);
      char text[32];
      std::snprintf(text, sizeof(text), "%.2g%%",
                    100.0 * cell.relative_rms_error);
      panel.cell_text.push_back(text);
    }
  }
  chart.panels = {panel};
  chart.lo = 1e-3;
  chart.hi = 1.0;
  chart.log_scale = true;
  chart.legend = "rel. rms error";
  chart.outline_above = true;
  chart.threshold = 0.01;
  chart.threshold_label = "red outline: error > 1 % (outside the regime)";
  // Both written before either is renamed into place would need a
  // transaction; the CSV goes first so that a chart never lacks its data.
  WriteFileAtomically(csv_path, SlabErrorMapCsv(map));
  WriteHeatMapPng(chart, png_path);
}

}  // namespace clothfit
