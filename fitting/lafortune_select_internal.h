// The folds of the held-out selections (fitting/lafortune_select.h,
// lafortune_level_select.h): k-fold over a table's lights, so that a
// candidate is judged at light directions it never saw. For fitting/*.cc
// only.
#pragma once

#include <functional>
#include <vector>

#include "fitting/lafortune_samples.h"
#include "fitting/model_selection.h"
#include "io/table.h"
#include "models/evaluate.h"

namespace clothfit {

// The fold of each row: its light's index among the table's distinct
// lights (ViewIndex: first appearance, equal to 1e-9), modulo `folds`; the
// number of distinct lights in *lights.
std::vector<int> LightFolds(const MeasurementTable& table, int folds,
                            int* lights);

// LightFolds, throwing InputError naming the table when it has fewer
// distinct lights than folds.
std::vector<int> RequireLightFolds(const MeasurementTable& table, int folds,
                                   int* lights);

// The table without the rows of fold f.
MeasurementTable WithoutFold(const MeasurementTable& table,
                             const std::vector<int>& fold, int f);

// Adds the squared errors and squared values over the reflection rows
// (wi.z, wo.z > 0) of fold `only` (every fold: only < 0) of the model
// model_of(row) (null: the row is skipped), in the table's quantity and
// channels, and counts them in *n (may be null).
void AddFoldErrors(const MeasurementTable& table, const std::vector<int>& fold,
                   int only,
                   const std::function<const ModelParams*(size_t)>& model_of,
                   double* se, double* ss, int* n);

// A candidate's training scores from its squared errors se, squared
// values ss and count n over every row (AddFoldErrors with only < 0):
// relative_rms and, with c->free_parameters set, the BIC (BicOfRss).
void SetTrainingScores(double se, double ss, int n, CandidateReport* c);

}  // namespace clothfit
