// The chart of the single-scattering slab's error against Monte Carlo
// (data_synthetic/slab_error_map.h): a heat map over tau x albedo.
#pragma once

#include <string>

#include "data_synthetic/slab_error_map.h"

namespace clothfit {

// Writes the PNG heat map (columns tau, rows albedo with the highest on
// top, colour log10 of the relative rms error, cells above 1 % outlined)
// and the CSV, each atomically.
void WriteSlabErrorMap(const SlabErrorMap& map, const std::string& png_path,
                       const std::string& csv_path);

}  // namespace clothfit
