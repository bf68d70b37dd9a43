#include "fitting/sheen_conversion.h"

#include <cmath>

#include "io/input_error.h"

namespace clothfit {

MeasurementTable ReflectionGrid(const ModelParams& model) {
  if (!ModelPredicts(model, Quantity::kCosineWeighted)) {
    throw InputError(std::string("a ") + ModelName(model) +
                     " model does not reflect light: it has no glTF "
                     "material");
  }
  std::vector<glm::dvec3> dirs;
  for (int i = 0; i < 9; ++i) {
    for (int k = 0; k < 12; ++k) {
      dirs.push_back(
          DirectionFromAngles(Radians(5.0 + 10.0 * i), Radians(30.0 * k)));
    }
  }
  MeasurementTable table;
  table.source = std::string(ModelName(model)) + " model";
  table.quantity = Quantity::kCosineWeighted;
  table.channels = 3;
  for (const glm::dvec3& wi : dirs) {
    for (const glm::dvec3& wo : dirs) {
      TableRow row;
      row.wi = wi;
      row.wo = wo;
      row.value = Evaluate(model, wi, wo, Quantity::kCosineWeighted);
      table.rows.push_back(row);
    }
  }
  return table;
}

SheenConversion ConvertToSheen(const MeasurementTable& table,
                               const NoiseModel& noise) {
  SheenFitOptions options;
  options.solver.noise = noise;
  const SheenFitResult fit = FitSheen(table, options);
  SheenConversion out;
  out.params = fit.params;
  out.report = fit.report;
  out.rows = static_cast<int>(table.rows.size());
  out.quantity = QuantityName(table.quantity);
  double diff = 0.0, data = 0.0;
  int n = 0;
  for (const TableRow& row : table.rows) {
    const glm::dvec3 m = Value(fit.params, row.wi, row.wo, table.quantity);
    for (int c = 0; c < table.channels; ++c) {
      diff += Sqr(m[c] - row.value[c]);
      data += Sqr(row.value[c]);
      ++n;
    }
  }
  out.rms = n > 0 ? std::sqrt(diff / n) : 0.0;
  out.relative_rms = data > 0.0 ? std::sqrt(diff / data) : 0.0;
  return out;
}

}  // namespace clothfit
