#include "fitting/sheen_conversion.h"

#include <cmath>

#include "io/input_error.h"

namespace clothfit {

MeasurementTable ReflectionGrid(const ModelParams& model, int polar,
                                int azimuth) {
  if (!ModelPredicts(model, Quantity::kCosineWeighted)) {
    throw InputError(std::string("a ") + ModelName(model) +
                     " model does not reflect light: it has no glTF "
                     "material");
  }
  std::vector<glm::dvec3> dirs;
  for (int i = 0; i < polar; ++i) {
    for (int k = 0; k < azimuth; ++k) {
      dirs.push_back(DirectionFromAngles(Radians((i + 0.5) * 90.0 / polar),
                                         Radians(360.0 * k / azimuth)));
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

void AddGridError(const ModelParams& source, const SheenParams& sheen,
                  int polar, int azimuth, double* diff2, double* data2) {
  const MeasurementTable grid = ReflectionGrid(source, polar, azimuth);
  for (const TableRow& row : grid.rows) {
    const glm::dvec3 m = Value(sheen, row.wi, row.wo, grid.quantity);
    for (int c = 0; c < 3; ++c) {
      *diff2 += Sqr(m[c] - row.value[c]);
      *data2 += Sqr(row.value[c]);
    }
  }
}

}  // namespace clothfit
