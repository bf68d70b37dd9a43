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

// Null when the paper's model conserves energy by itself.
inline std::shared_ptr<const EnergyBound> EnergyBoundOf(ThreadParams p) {
  p.energy_bound = nullptr;
  p.scale = std::max(1.0, p.scale);
  return ComputeEnergyBound([&](const glm::dvec3& wi, const glm::dvec3& wo) {
    return Rho(p, wi, wo);
  });
}

// A weave's threads run along its rotation: the azimuth search starts there.
// Evaluated with the samples' frames computed once (models/prepared.h).
inline std::shared_ptr<const EnergyBound> EnergyBoundOf(ClothParams c) {
  c.energy_bound = nullptr;
  c.scale = std::max(1.0, c.scale);
  const PreparedCloth<double> prepared = PrepareCloth<double>(c);
  return ComputeEnergyBound(
      [&](const glm::dvec3& wi, const glm::dvec3& wo) {
        return Rho(prepared, wi, wo);
      },
      c.rotation_deg * kPi / 180.0);
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
