// The energy bound (models/energy_bound.h) of a thread or cloth parameter
// set: computed from the paper's model at those parameters (any bound they
// carry ignored), so that a model with its own bound attached conserves
// energy on both sides everywhere on the hemisphere. What a fit writes, a
// preset gives and `synth` draws.
//
// The model's `scale` enters as max(1, scale): a factor below 1 (a table on
// a dimmer calibration, `fit --fit-scale`) dims a model that conserves
// energy, which then still does, and keeps the bound of the surface itself,
// so that a scaled table of a bounded surface is the bounded model times
// the factor; a factor above 1 is bounded with the model it brightens.
#pragma once

#include <algorithm>
#include <memory>
#include <variant>

#include "models/energy_bound.h"
#include "models/evaluate.h"
#include "models/prepared.h"

namespace clothfit {

namespace bounded_internal {

// The paper's model at p, its bound dropped and its scale max(1, scale):
// rho(wi, wo), the cosine-weighted value.
struct ThreadRho {
  ThreadParams p;
  glm::dvec3 operator()(const glm::dvec3& wi, const glm::dvec3& wo) const {
    return Rho(p, wi, wo);
  }
};
// Evaluated with the samples' frames computed once (models/prepared.h).
struct PreparedClothRho {
  PreparedCloth<double> p;
  glm::dvec3 operator()(const glm::dvec3& wi, const glm::dvec3& wo) const {
    return Rho(p, wi, wo);
  }
};

inline ThreadRho PaperRho(ThreadParams p) {
  p.energy_bound = nullptr;
  p.scale = std::max(1.0, p.scale);
  return {p};
}
inline PreparedClothRho PaperRho(ClothParams c) {
  c.energy_bound = nullptr;
  c.scale = std::max(1.0, c.scale);
  return {PrepareCloth<double>(c)};
}

// Where the azimuth search starts: a weave's threads run along its
// rotation.
inline double FirstAzimuth(const ThreadParams&) { return 0.0; }
inline double FirstAzimuth(const ClothParams& c) {
  return c.rotation_deg * kPi / 180.0;
}

}  // namespace bounded_internal

// The bound of a thread or cloth: null when the paper's model conserves
// energy by itself. `plan`, when not null, receives where the tables'
// entries were taken (models/energy_bound.h).
template <typename P>
std::shared_ptr<const EnergyBound> EnergyBoundOf(
    const P& p, EnergyBoundPlan* plan = nullptr) {
  return ComputeEnergyBound(bounded_internal::PaperRho(p),
                            bounded_internal::FirstAzimuth(p), plan);
}

// The tables of `plan` at the parameters p of a thread or cloth (always a
// bound, even where the paper's model would need none): what a fit of the
// bounded model through that plan evaluates.
template <typename P>
std::shared_ptr<const EnergyBound> EnergyBoundByPlan(
    const P& p, const EnergyBoundPlan& plan) {
  auto bound = std::make_shared<EnergyBound>();
  bound->light.resize(plan.light.size());
  bound->view.resize(plan.view.size());
  EnergyBoundTables<double>(plan, bounded_internal::PaperRho(p),
                            bound->light.data(), bound->view.data());
  return bound;
}

// `plan` refined to the crests of the albedos of a thread or cloth at p
// (RefineEnergyBoundPlan).
template <typename P>
EnergyBoundPlan RefineEnergyBoundPlanAt(const P& p,
                                        const EnergyBoundPlan& plan) {
  return RefineEnergyBoundPlan(bounded_internal::PaperRho(p), plan);
}

// `params` with the bound of its own values attached (a thread or cloth);
// every other model as it is (Lafortune, slab, holes, sheen conserve energy
// by their own rules).
inline ModelParams WithEnergyBound(ModelParams params) {
  if (auto* p = std::get_if<ThreadParams>(&params)) {
    p->energy_bound = EnergyBoundOf(*p);
  } else if (auto* c = std::get_if<ClothParams>(&params)) {
    c->energy_bound = EnergyBoundOf(*c);
  }
  return params;
}

}  // namespace clothfit
