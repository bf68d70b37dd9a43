// The synthetic holes problem shared by `clothfit bench` and its stability
// study: transmittance of a mask at given views, ray-traced
// (data_synthetic/holes_truth.h) or the model's own, and the held-out error
// of a fitted thickness against such a table.
#pragma once

#include <vector>

#include "holes/hole_texture.h"
#include "io/table.h"
#include "models/holes.h"

namespace clothfit {

// A one-channel transmittance table of `mask` with columns of `truth`: one
// row per (theta, phi) in degrees, the tile's ray-traced ratios
// (`samples` rays per texel and axis) through TransmittanceOfRatios.
MeasurementTable HolesTruthTable(const Mask& mask, const HolesParams& truth,
                                 const std::vector<double>& thetas_deg,
                                 const std::vector<double>& phis_deg,
                                 int samples);

// The same views with the model's own values on `tile`
// (holes/hole_texture.h HolesTileOf) instead of the ray-traced truth: data
// the model can explain exactly, for the stability study (which tests the
// fit, not the model's error against ray tracing).
MeasurementTable HolesModelTable(const HolesTile& tile,
                                 const HolesParams& truth,
                                 const std::vector<double>& thetas_deg,
                                 const std::vector<double>& phis_deg);

// Relative RMS of the fitted model on `tile` against the values of `truth`
// (a table of held-out views).
double HolesHeldOutError(const HolesParams& fitted, const HolesTile& tile,
                         const MeasurementTable& truth);

}  // namespace clothfit
