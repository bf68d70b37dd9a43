// How a measured value's error enters every fit: the one weighting of the
// residuals and the noise model behind it. The residual of channel c of a
// row is
//   r_c = (model_c - measured_c) sqrt(weight) / sigma_c,
// and half the sum of r_c^2 is the cost Ceres minimises. sigma comes from
// the noise model:
//   table     the table's sigma column (its 1-sigma errors);
//   relative  sigma = F max(|measured|, floor): noise proportional to the
//             value, as reflectance measurements have it; the floor keeps
//             values near 0 from weighing without limit;
//   absolute  sigma = F for every row.
// The default: the table's sigma where it has a sigma column, else
// relative. Relative sigma is taken from the measured value for a first
// solve, then from the fitted model's value for the final one
// (iteratively reweighted least squares: unbiased, where weights from
// noisy values favour the values that came out low). The level F may be given;
// otherwise the weights are those of F = 1 and the fit estimates F from its
// residuals (F^2 = 2 cost / dof): the standard deviations then come from a
// covariance that does not depend on that estimate (the sandwich,
// least_squares.cc). A fit that sees a value as another quantity (rho = f wi.z
// for Lafortune's lobes) scales sigma with it.
#pragma once

#include <cmath>
#include <functional>
#include <glm/vec3.hpp>
#include <string>
#include <vector>

#include "io/table.h"

namespace clothfit {

enum class NoiseKind { kDefault, kTable, kRelative, kAbsolute };

struct NoiseModel {
  // kDefault: kTable for a table with a sigma column, else kRelative.
  NoiseKind kind = NoiseKind::kDefault;
  // F: the relative error (kRelative) or sigma itself (kAbsolute); 0: not
  // known, estimated from the residuals.
  double level = 0.0;
  // kRelative: values below the floor weigh as the floor; 0: 1 % of the
  // median |value| of the channel in the table.
  double floor = 0.0;
};

// "table" | "relative" | "absolute" ("default" for kDefault).
const char* NoiseKindName(NoiseKind kind);

// The weighting of one table under a noise model. Throws InputError for
// kTable on a table without a sigma column, and for a negative level or
// floor.
class Weighting {
 public:
  Weighting(const MeasurementTable& table, const NoiseModel& noise);
  // The same for a table read row by row: `table` gives the columns (its
  // rows are not read), and channel_values(c) the |value| of channel c
  // of every row, called only where the default floor needs them.
  Weighting(
      const MeasurementTable& table, const NoiseModel& noise,
      const std::function<std::vector<double>(int channel)>& channel_values);

  // The noise model in effect (never kDefault).
  NoiseKind kind() const { return kind_; }
  // Whether sigma is known in data units (the table's, or a given level):
  // then the covariance needs no estimate of the noise level.
  bool LevelKnown() const { return kind_ == NoiseKind::kTable || level_ > 0; }
  double level() const { return level_; }
  // F as the weights use it: the level, or 1 while it is estimated.
  double WeightLevel() const { return level_ > 0.0 ? level_ : 1.0; }
  const glm::dvec3& floor() const { return floor_; }

  // sigma of a row's value per channel: of the measured value (the
  // first solve's weights, and the start search's).
  glm::dvec3 Sigma(const TableRow& row) const;
  // The factor sqrt(weight) / sigma of its residuals.
  glm::dvec3 Scale(const TableRow& row) const;
  // Whether sigma depends on the value (relative noise): then the fit
  // solves again with sigma of the fitted model's value (ScaleAt), which
  // removes the bias of weights taken from noisy values (about -2 F^2
  // relative, 0.16 sigma of a thread's albedo at F = 1 %).
  bool DependsOnModel() const { return kind_ == NoiseKind::kRelative; }
  // The factor sqrt(weight) / sigma with sigma of the value `model` in
  // place of the measured one.
  glm::dvec3 ScaleAt(const TableRow& row, const glm::dvec3& model) const;
  // The inverse-variance weight weight / sigma'^2 of its value seen as k
  // times the tabulated quantity (sigma' = k sigma): what merged samples
  // add up (sum_i w_i (m - y_i)^2 = W (m - y_mean)^2 + const with
  // W = sum_i w_i).
  glm::dvec3 InverseVariance(const TableRow& row, double k) const;

 private:
  // Relative sigma of a value v: F max(|v|, floor).
  glm::dvec3 RelativeSigma(const glm::dvec3& v) const;

  NoiseKind kind_;
  double level_;
  glm::dvec3 floor_{0.0};
};

// One residual: (model - measured) scale, for any scalar type.
template <typename T>
T WeightedResidual(const T& model, double measured, double scale) {
  return (model - T(measured)) * T(scale);
}

}  // namespace clothfit
