// How a measured value's error enters every fit: the one weighting of the
// residuals (model - measured) / sigma, so that a noise model changes the
// fits in this one place. A row gives sigma (1 without a sigma column)
// and a weight; the residual of channel c is
//   r_c = (model_c - measured_c) sqrt(weight) / sigma_c,
// and half the sum of r_c^2 is the cost Ceres minimises. A fit that sees a
// value as another quantity (rho = f wi.z for Lafortune's lobes) scales
// sigma with it.
#pragma once

#include <cmath>
#include <glm/vec3.hpp>

#include "io/table.h"

namespace clothfit {

// The factor sqrt(weight) / sigma of a row's residuals, per channel.
inline glm::dvec3 ResidualScale(const TableRow& row) {
  return glm::dvec3(std::sqrt(row.weight)) / row.sigma;
}

// The inverse-variance weight weight / sigma'^2 of a row's value seen as
// k times the tabulated quantity (sigma' = k sigma), per channel: what
// merged samples add up (sum_i w_i (m - y_i)^2 = W (m - y_mean)^2 +
// const with W = sum_i w_i).
inline glm::dvec3 InverseVariance(const TableRow& row, double k) {
  const glm::dvec3 sigma = row.sigma * k;
  return row.weight / (sigma * sigma);
}

// One residual: (model - measured) scale, for any scalar type.
template <typename T>
T WeightedResidual(const T& model, double measured, double scale) {
  return (model - T(measured)) * T(scale);
}

}  // namespace clothfit
