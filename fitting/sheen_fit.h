// Fits the glTF cloth material (models/sheen.h: a dielectric
// metallic-roughness base under the KHR_materials_sheen layer) to a
// reflection table (brdf or cosine_weighted): base_color (rgb), roughness,
// sheen_color (rgb) and sheen_roughness, all within their glTF ranges.
// What `clothfit fit --model sheen` and the glTF export
// (fitting/gltf_conversion.h) solve.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "fitting/fit_result.h"
#include "io/table.h"
#include "models/sheen.h"

namespace clothfit {

struct SheenFitOptions {
  SolverOptions solver;
  // Joins the start grid; fixed entries keep it (SheenParams() otherwise).
  std::optional<SheenParams> init;
  // Flat names ("roughness", "sheen_color", "base_color_r", ...) held at
  // their initial value; `free_only`, when not empty, frees only these.
  std::vector<std::string> fix;
  std::vector<std::string> free_only;
  // Multi-start: the solver runs from the best-ranked starts of a grid over
  // the two roughnesses until this many reach the same lowest cost.
  int solve_starts = 2;
};

using SheenFitResult = FitResult<SheenParams>;

// Throws InputError for a transmittance table and for unknown names in
// fix/free_only.
SheenFitResult FitSheen(const MeasurementTable& table,
                        const SheenFitOptions& options);

}  // namespace clothfit
