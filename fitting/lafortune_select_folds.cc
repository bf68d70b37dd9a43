#include <cmath>
#include <string>
#include <vector>

#include "fitting/lafortune_select_internal.h"
#include "io/input_error.h"

namespace clothfit {

std::vector<int> LightFolds(const MeasurementTable& table, int folds,
                            int* lights) {
  const ViewIndex index(table);
  std::vector<int> fold(table.rows.size());
  for (size_t i = 0; i < table.rows.size(); ++i) {
    fold[i] = index.RowLight(i) % folds;
  }
  *lights = index.lights();
  return fold;
}

MeasurementTable WithoutFold(const MeasurementTable& table,
                             const std::vector<int>& fold, int f) {
  MeasurementTable out = table;
  out.rows.clear();
  for (size_t i = 0; i < table.rows.size(); ++i) {
    if (fold[i] != f) out.rows.push_back(table.rows[i]);
  }
  return out;
}

void AddFoldErrors(const MeasurementTable& table, const std::vector<int>& fold,
                   int only,
                   const std::function<const ModelParams*(size_t)>& model_of,
                   double* se, double* ss, int* n) {
  for (size_t i = 0; i < table.rows.size(); ++i) {
    const TableRow& row = table.rows[i];
    if ((only >= 0 && fold[i] != only) || !IsReflectionRow(row)) continue;
    const ModelParams* model = model_of(i);
    if (model == nullptr) continue;
    const glm::dvec3 m = Evaluate(*model, row.wi, row.wo, table.quantity);
    for (int c = 0; c < table.channels; ++c) {
      const double d = m[c] - row.value[c];
      *se += d * d;
      *ss += row.value[c] * row.value[c];
      if (n != nullptr) ++*n;
    }
  }
}

void SetTrainingScores(double se, double ss, int n, CandidateReport* c) {
  c->relative_rms = ss > 0.0 ? std::sqrt(se / ss) : 0.0;
  c->bic = n > 0 ? BicOfRss(se, n, c->free_parameters) : 0.0;
}

std::vector<int> RequireLightFolds(const MeasurementTable& table, int folds,
                                   int* lights) {
  const std::vector<int> fold = LightFolds(table, folds, lights);
  if (*lights < folds) {
    throw InputError(
        table.source + ": --select heldout with " + std::to_string(folds) +
        " folds needs at least " + std::to_string(folds) +
        " distinct light directions, got " + std::to_string(*lights));
  }
  return fold;
}

}  // namespace clothfit
