// The chart of the single-scattering slab's error against Monte Carlo
// (data_synthetic/slab_error_map.h): a heat map over tau x albedo.
#pragma once

#include <string>

#include "charts/heat_map.h"
#include "data_synthetic/slab_error_map.h"

namespace clothfit {

// The heat map: columns tau, rows albedo with the highest on top, the
// relative rms error in percent (cells, colour bar and threshold in the
// one unit), colour log10 of it, cells above 1 % outlined.
HeatMap SlabErrorHeatMap(const SlabErrorMap& map);

// Writes SlabErrorHeatMap as PNG and the CSV, each atomically.
void WriteSlabErrorMap(const SlabErrorMap& map, const std::string& png_path,
                       const std::string& csv_path);

}  // namespace clothfit
