// Fits the thickness h (and optionally the wall colour) of a holed layer
// (David-Babin 2022; SPEC §3.5) to a table of measured transmittance versus
// view direction (quantity: transmittance; only wo is used) for a given
// mask: model = rho_transparent + wall_color rho_occluded of the whole
// tile (models/holes.h HolesTransmittance), with the ratios of Algorithm
// 3.1 or of the extension (holes/hole_texture.h).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "fitting/fit_result.h"
#include "holes/hole_texture.h"
#include "io/table.h"
#include "models/holes.h"

namespace clothfit {

struct HolesFitOptions {
  SolverOptions solver;
  // Starting values (they join the start grid) and the values of fixed
  // parameters; HolesParams() defaults without.
  std::optional<HolesParams> init;
  // Free the wall colour (one value for one-channel tables); by default
  // only thickness_texels is free.
  bool fit_wall_color = false;
  // Names (HolesParamNames(), "wall_color" for all three) held at their
  // initial value / the only free ones, after fit_wall_color.
  std::vector<std::string> fix;
  std::vector<std::string> free_only;
  HoleMethod method = HoleMethod::kExtension;
  // Pyramid level whose texels are evaluated and averaged over the tile;
  // -1: the top (1 x 1) level. Algorithm 3.1 gives the same at every level;
  // the extension is exact on rectangular holes at every level, and on
  // irregular masks its error depends on the level (docs/holes.md); lower
  // levels cost more per evaluation.
  int level = -1;
};

struct HolesFitResult {
  HolesParams params;
  FitReport report;
};

// Throws InputError for a table that is not transmittance, a level out of
// range, the extension without distances in `texture`, and unknown names
// in fix/free_only.
HolesFitResult FitHoles(const MeasurementTable& table,
                        const HoleTexture& texture,
                        const HolesFitOptions& options);

}  // namespace clothfit
