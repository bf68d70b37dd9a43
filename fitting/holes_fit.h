// Fits the thickness h (and optionally the wall colour) of a holed layer
// (David-Babin 2022; docs/models.md) to a table of measured transmittance
// versus view direction (quantity: transmittance; only wo is used) for a given
// mask's tile: model = rho_transparent + wall_color rho_occluded of the
// whole tile (models/holes_tile.h HolesTransmittance), with the ratios of
// Algorithm 3.1 or of the extension. The tile (a level of the mask's
// count pyramid) comes from holes/hole_texture.h HolesTileOf.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "fitting/fit_result.h"
#include "io/table.h"
#include "models/holes_tile.h"

namespace clothfit {

struct HolesFitOptions {
  SolverOptions solver;
  // Starting values (they join the start grid) and the values of fixed
  // parameters; HolesParams() defaults without.
  std::optional<HolesParams> init;
  // Free the wall colour (one value for one-channel tables); by default
  // only thickness_texels is free.
  bool fit_wall_color = false;
  // Names (the flat names of the holes table, "wall_color" for all three)
  // held at their initial value / the only free ones, after fit_wall_color.
  std::vector<std::string> fix;
  std::vector<std::string> free_only;
};

using HolesFitResult = FitResult<HolesParams>;

// Throws InputError for a table that is not transmittance, invalid initial
// parameters and unknown names in fix/free_only.
HolesFitResult FitHoles(const MeasurementTable& table, const HolesTile& tile,
                        const HolesFitOptions& options);

}  // namespace clothfit
