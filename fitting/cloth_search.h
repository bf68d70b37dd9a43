// The starts of the cloth fit. The model's entries are of two kinds: the
// weave's geometry (rotation, tangent offsets, coverages) and eta, which
// move the tangent samples and the normalisation Q and leave many local
// minima; and per thread the widths, albedo, kd, plus the diffuse term and
// the scale. For a given geometry the second kind is searched as in
// fitting/start_search.h (a grid over the widths, the linear entries in
// closed form). The first kind, where free, is covered by a space-filling
// design (a Halton sequence over each free entry's design range), the
// initial values being its first point. Every point is ranked by the cost
// of its best widths and linear entries; the best points are the solver's
// starts. Internal to fitting/.
#pragma once

#include <vector>

#include "fitting/cloth_weave_internal.h"
#include "fitting/residual_weight.h"

namespace clothfit {

struct ClothStartProblem {
  const MeasurementTable* table = nullptr;
  const Weighting* weighting = nullptr;
  const Weave* weave = nullptr;
  const std::vector<ParameterSpec>* specs = nullptr;  // which are free
  std::vector<double> init;   // a solver vector (stick coordinates)
  // Per row of *table, a constant factor on the model (the energy bound's,
  // fitting/energy_bound_fit_internal.h); empty: 1.
  std::vector<double> row_factor;
  bool search_widths = true;  // false: the widths stay at init
  // Points of the design besides the initial one (used only when a
  // geometry entry or eta is free).
  int design_points = 0;
};

struct ClothStarts {
  std::vector<std::vector<double>> starts;  // solver vectors, best first
  int design_points = 0;                    // geometries tried, the init's too
};

// The `keep` best starts.
ClothStarts SearchClothStarts(const ClothStartProblem& problem, int keep);

}  // namespace clothfit
