#include "bench/slab_error_chart.h"

#include <cstdio>

#include "io/atomic_file.h"
#include "io/text_util.h"

namespace clothfit {

HeatMap SlabErrorHeatMap(const SlabErrorMap& map) {
  const SlabErrorMapOptions& o = map.options;
  HeatMap chart;
  chart.title =
      "single-scattering slab vs Monte Carlo: relative rms error of f_r, f_t";
  chart.x_title = "optical thickness tau";
  chart.y_title = "albedo A";
  for (double tau : o.taus)
    chart.x_labels.push_back(text_util::FormatNumber(tau, 6));
  const size_t n_tau = o.taus.size();
  HeatMapPanel panel;
  for (size_t a = o.albedos.size(); a-- > 0;) {  // highest albedo on top
    chart.y_labels.push_back(text_util::FormatNumber(o.albedos[a], 6));
    for (size_t t = 0; t < n_tau; ++t) {
      const SlabErrorCell& cell = map.cells[a * n_tau + t];
      const double percent = 100.0 * cell.relative_rms_error;
      panel.values.push_back(percent);
      char text[32];
      std::snprintf(text, sizeof(text), "%.2g%%", percent);
      panel.cell_text.push_back(text);
    }
  }
  chart.panels = {panel};
  chart.lo = 0.1;
  chart.hi = 100.0;
  chart.log_scale = true;
  chart.legend = "rel. rms error [%]";
  chart.unit = "%";
  chart.outline_above = true;
  chart.threshold = 1.0;
  chart.threshold_label = "red outline: error > 1 % (outside the regime)";
  return chart;
}

void WriteSlabErrorMap(const SlabErrorMap& map, const std::string& png_path,
                       const std::string& csv_path) {
  const HeatMap chart = SlabErrorHeatMap(map);
  // Both written before either is renamed into place would need a
  // transaction; the CSV goes first so that a chart never lacks its data.
  WriteFileAtomically(csv_path, SlabErrorMapCsv(map));
  WriteHeatMapPng(chart, png_path);
}

}  // namespace clothfit
