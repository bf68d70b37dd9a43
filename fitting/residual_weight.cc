#include "fitting/residual_weight.h"

#include <algorithm>
#include <glm/common.hpp>
#include <vector>

#include "io/input_error.h"

namespace clothfit {

const char* NoiseKindName(NoiseKind kind) {
  switch (kind) {
    case NoiseKind::kTable:
      return "table";
    case NoiseKind::kRelative:
      return "relative";
    case NoiseKind::kAbsolute:
      return "absolute";
    case NoiseKind::kDefault:
      break;
  }
  return "default";
}

Weighting::Weighting(const MeasurementTable& table, const NoiseModel& noise)
    : Weighting(table, noise, [&table](int c) {
        std::vector<double> values;
        values.reserve(table.rows.size());
        for (const TableRow& row : table.rows)
          values.push_back(std::abs(row.value[c]));
        return values;
      }) {}

Weighting::Weighting(
    const MeasurementTable& table, const NoiseModel& noise,
    const std::function<std::vector<double>(int channel)>& channel_values)
    : kind_(noise.kind), level_(noise.level) {
  const std::string name = table.source.empty() ? "table" : table.source;
  if (!(noise.level >= 0.0) || !std::isfinite(noise.level)) {
    throw InputError("noise level: must be >= 0, got " +
                     std::to_string(noise.level));
  }
  if (!(noise.floor >= 0.0) || !std::isfinite(noise.floor)) {
    throw InputError("noise floor: must be >= 0, got " +
                     std::to_string(noise.floor));
  }
  if (kind_ == NoiseKind::kDefault) {
    kind_ = table.has_sigma ? NoiseKind::kTable : NoiseKind::kRelative;
  }
  if (kind_ == NoiseKind::kTable) {
    if (!table.has_sigma) {
      throw InputError(name + ": no sigma column for the noise model 'table'");
    }
    level_ = 0.0;
  }
  if (kind_ != NoiseKind::kRelative) return;
  if (noise.floor > 0.0) {
    floor_ = glm::dvec3(noise.floor);
    return;
  }
  // The default floor (io/table.h).
  for (int c = 0; c < 3; ++c) floor_[c] = RelativeNoiseFloor(channel_values(c));
}

glm::dvec3 Weighting::RelativeSigma(const glm::dvec3& v) const {
  return WeightLevel() * glm::max(glm::abs(v), floor_);
}

glm::dvec3 Weighting::Sigma(const TableRow& row) const {
  switch (kind_) {
    case NoiseKind::kTable:
      return row.sigma;
    case NoiseKind::kRelative:
      return RelativeSigma(row.value);
    default:
      return glm::dvec3(WeightLevel());
  }
}

glm::dvec3 Weighting::ScaleAt(const TableRow& row,
                              const glm::dvec3& model) const {
  if (kind_ != NoiseKind::kRelative) return Scale(row);
  return glm::dvec3(std::sqrt(row.weight)) / RelativeSigma(model);
}

glm::dvec3 Weighting::Scale(const TableRow& row) const {
  return glm::dvec3(std::sqrt(row.weight)) / Sigma(row);
}

glm::dvec3 Weighting::InverseVariance(const TableRow& row, double k) const {
  const glm::dvec3 sigma = Sigma(row) * k;
  return row.weight / (sigma * sigma);
}

}  // namespace clothfit
