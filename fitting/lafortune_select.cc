#include "fitting/lafortune_select.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "io/input_error.h"
#include "models/evaluate.h"

namespace clothfit {
namespace {

// The fold of each row: its light's index among the table's distinct
// lights (first appearance, equal to 1e-9), modulo `folds`.
std::vector<int> LightFolds(const MeasurementTable& table, int folds,
                            int* lights) {
  std::vector<glm::dvec3> seen;
  std::vector<int> fold(table.rows.size());
  for (size_t i = 0; i < table.rows.size(); ++i) {
    const glm::dvec3& wi = table.rows[i].wi;
    size_t k = 0;
    while (k < seen.size() && glm::length(seen[k] - wi) > 1e-9) ++k;
    if (k == seen.size()) seen.push_back(wi);
    fold[i] = static_cast<int>(k % folds);
  }
  *lights = static_cast<int>(seen.size());
  return fold;
}

// Whether a row is one a reflection model predicts (wi.z, wo.z > 0).
bool Reflection(const TableRow& row) {
  return row.wi.z > 0.0 && row.wo.z > 0.0;
}

// Adds the squared errors and squared values of `model` over the
// reflection rows of fold `only` (every fold: only < 0), in the table's
// quantity and channels, and counts them in *n.
void Errors(const LafortuneModel& model, const MeasurementTable& table,
            const std::vector<int>& fold, int only, double* se, double* ss,
            int* n) {
  const ModelParams params = model;
  for (size_t i = 0; i < table.rows.size(); ++i) {
    const TableRow& row = table.rows[i];
    if ((only >= 0 && fold[i] != only) || !Reflection(row)) continue;
    const glm::dvec3 m = Evaluate(params, row.wi, row.wo, table.quantity);
    for (int c = 0; c < table.channels; ++c) {
      const double d = m[c] - row.value[c];
      *se += d * d;
      *ss += row.value[c] * row.value[c];
      ++*n;
    }
  }
}

MeasurementTable Without(const MeasurementTable& table,
                         const std::vector<int>& fold, int f) {
  MeasurementTable out = table;
  out.rows.clear();
  for (size_t i = 0; i < table.rows.size(); ++i) {
    if (fold[i] != f) out.rows.push_back(table.rows[i]);
  }
  return out;
}

}  // namespace

LafortuneSelection SelectLafortuneHeldOut(const MeasurementTable& table,
                                          const LafortuneMipOptions& options,
                                          int folds) {
  folds = std::clamp(folds, 2, 20);
  int lights = 0;
  const std::vector<int> fold = LightFolds(table, folds, &lights);
  if (lights < folds) {
    throw InputError(
        table.source + ": --select heldout with " + std::to_string(folds) +
        " folds needs at least " + std::to_string(folds) +
        " distinct light directions, got " + std::to_string(lights));
  }
  LafortuneSelection out;
  out.report.tolerance = 0.0;
  double best = HUGE_VAL;
  for (int lut = 0; lut < 2; ++lut) {
    for (int k = 0; k <= 3; ++k) {
      LafortuneMipOptions o = options;
      o.tolerance = 0.0;
      o.fit.lobes = k;
      o.fit.lookup_table = lut == 1;
      LafortuneFitResult all = FitLafortuneTable(table, o);
      if (lut == 1 && all.report.lut_views_fitted == 0) continue;
      CandidateReport c;
      c.description = std::to_string(k) + " lobe(s), " +
                      (lut == 1 ? "lookup table" : "no lookup table");
      c.free_parameters =
          table.channels * (1 + 4 * k) +
          (lut == 1 ? table.channels * all.report.lut_views_fitted : 0);
      c.usable = all.report.usable;
      double se = 0.0, ss = 0.0;
      int n = 0;
      Errors(all.params, table, fold, -1, &se, &ss, &n);
      c.relative_rms = ss > 0.0 ? std::sqrt(se / ss) : 0.0;
      c.bic = n > 0 ? n * std::log(std::max(se, 1e-300) / n) +
                          c.free_parameters * std::log(static_cast<double>(n))
                    : 0.0;
      double hse = 0.0, hss = 0.0;
      int hn = 0;
      for (int f = 0; f < folds && c.usable; ++f) {
        const LafortuneFitResult part =
            FitLafortuneTable(Without(table, fold, f), o);
        c.usable = part.report.usable;
        Errors(part.params, table, fold, f, &hse, &hss, &hn);
      }
      c.heldout_relative_rms =
          c.usable && hss > 0.0 ? std::sqrt(hse / hss) : -1.0;
      // The lowest held-out error; on a tie the candidate tried first (fewer
      // lobes, no table).
      if (c.usable && c.heldout_relative_rms >= 0.0 &&
          c.heldout_relative_rms < best) {
        best = c.heldout_relative_rms;
        out.report.chosen = static_cast<int>(out.report.candidates.size());
        out.fit = std::move(all);
      }
      out.report.candidates.push_back(c);
    }
  }
  char reason[200];
  if (out.report.chosen >= 0) {
    std::snprintf(reason, sizeof(reason),
                  "the lowest held-out relative rms (%d-fold over %d lights)",
                  folds, lights);
  } else {
    std::snprintf(reason, sizeof(reason), "no candidate reached a usable fit");
  }
  out.report.reason = reason;
  return out;
}

}  // namespace clothfit
