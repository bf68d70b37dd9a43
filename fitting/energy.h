// The white-furnace check of a fitted model (models/albedo.h): the largest
// directional albedo a(wo), in any channel, over a dense set of directions
// of the upper hemisphere (FurnaceDirections: the normal and rings from 15
// to 89 degrees). A model conserves energy when it is at most 1.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "fitting/fit_result.h"
#include "models/albedo.h"
#include "models/evaluate.h"

namespace clothfit {

struct EnergyCheck {
  double max_albedo = 0.0;              // over directions and channels
  glm::dvec3 direction{0.0, 0.0, 1.0};  // where (surface frame)
};

// A Lafortune texel: in closed form (LafortuneViewAlbedo) at
// FurnaceDirections(12) and at the lookup table's views.
EnergyCheck LafortuneEnergy(const LafortuneModel& m);

// Any model by quadrature (36 rings) at FurnaceDirections(8); a thread or
// cloth with an energy bound (models/bounded.h) on both sides
// (ModelViewAlbedo and ModelLightAlbedo: the paper's models are not
// reciprocal), without one on the view side; a Lafortune model by
// LafortuneEnergy.
EnergyCheck ModelEnergy(const ModelParams& p);

// The light side of a thread or cloth without an energy bound, which
// ModelEnergy leaves out: the largest integral of f(wi, wo) wo.z over the
// views (ModelLightAlbedo) at FurnaceDirections(8) and its wi. max_albedo
// < 0 for other models and bounded ones (ModelEnergy covers both sides).
EnergyCheck ModelLightSideEnergy(const ModelParams& p);

// The directional albedo a(wo) of any model (models/albedo.h), per
// channel: a Lafortune texel by LafortuneViewAlbedo, any other model by
// QuadratureViewAlbedo with `q` (ModelEnergy uses MakeHemisphereQuadrature
// (36)). The one directional albedo of a ModelParams (the plot's curve,
// the furnace check).
glm::dvec3 ModelViewAlbedo(const ModelParams& p, const glm::dvec3& wo,
                           const HemisphereQuadrature& q);

// The light-side albedo, the integral of f(wi, wo) wo.z over wo, by the
// quadrature q, per channel: what a surface lit from wi reflects in all.
glm::dvec3 ModelLightAlbedo(const ModelParams& p, const glm::dvec3& wi,
                            const HemisphereQuadrature& q);

// Lowers each stored view's T (per channel) to 1 / the bracket's albedo
// at that view where T times it exceeds 1 (LafortuneViewAlbedo at the
// stored views; `normal` the texel's, `views` the table's views in the
// surface frame); returns how many views were lowered.
int BoundLookupTableByEnergy(const LafortuneParams& p, const glm::dvec3& normal,
                             const std::vector<glm::dvec3>& views,
                             std::vector<glm::dvec3>* t);

// Records ModelEnergy of a fitted model in the report (max_albedo,
// max_albedo_at, and the light side's) unless the fit did (a Lafortune
// texel or a cloth fit).
// A thread is reported, not scaled: the published microcylinder thread
// exceeds 1 at grazing views along its axis by itself (docs/fitting.md).
void ReportModelEnergy(const ModelParams& fitted, FitReport* report);

// The fit's predictions at its optimum and the data they match:
// `pairs(visit)` calls visit(model, measured) for each, in turn (nothing
// held for all rows).
using PredictionPairs =
    std::function<void(const std::function<void(double, double)>&)>;

// The energy rule of a fit whose model has an overall factor (a cloth
// model's `scale`): when ModelEnergy(fitted) exceeds 1, *scale is
// multiplied by s = 1 / that albedo, so that what is written conserves
// energy, and the report's rms and relative_rms become the scaled
// model's (from `pairs`, visited only then). Records the check
// (max_albedo, max_albedo_at, energy_scale) and, when it scaled, marks
// the fit not converged (MarkEnergyScaled). Returns s (1: nothing
// scaled).
double ConserveEnergyByScale(const ModelParams& fitted,
                             const PredictionPairs& pairs, double* scale,
                             FitReport* report);

// A fit scaled to conserve energy (report->energy_scale < 1) is not
// converged: the message says where the model reflected more than it
// received and by what it was scaled (kept before any earlier message).
void MarkEnergyScaled(FitReport* report);

// Multiplies the albedo of every direction by s > 0: rho_d by s, each
// lobe's C by s^(1/N) (its value by s).
void ScaleLafortuneAlbedo(double s, LafortuneParams* p);

// "directional albedo 1.23 (at theta 85, phi 90 degrees)".
std::string DescribeEnergy(const EnergyCheck& e);

}  // namespace clothfit
