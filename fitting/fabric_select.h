// `clothfit fit --model auto`: which model family a measured fabric
// supports. Fits each candidate family to the whole table and to k folds
// of its rows (fold = row index mod k), scores each by the pooled relative
// RMS on the rows it did not see, and picks the lowest held-out error
// among the candidates whose whole-table fit converged (if none did, among
// the usable ones, and the choice says so). The parameter count and the
// BIC are reported beside it; the held-out error decides, because the
// BIC's parameter count treats every microcylinder entry as free while
// many are nearly undetermined on 200-row tables. A fold's fit starts from
// the candidate's whole-table solution (one start, no start search): it
// measures how well the family predicts rows it was not fitted to once
// its basin is found, at a sixth of the cost of searching every fold; the
// basin itself was chosen with every row, and the entries the whole table
// left undetermined or on a bound stay where it put them (HeldInFolds).
//
// Candidates, simplest first: a constant (Lambertian), 1 and 2 Lafortune
// lobes without lookup table, the thread, and the cloth with the plain
// (linen_plain) and satin (polyester_satin_charmeuse) weaves of Sadeghi et
// al. 2013, each as the paper's model and with the freedoms of
// models/microcylinder_cloth.h (rotation_deg, the tangent offsets, a
// Lambertian term; the plain weave also with free coverages). The cloth
// and thread fits start from generic thread values (GenericClothStart).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "fitting/fit_result.h"
#include "fitting/model_selection.h"
#include "io/table.h"
#include "models/evaluate.h"

namespace clothfit {

struct FabricSelectOptions {
  SolverOptions solver;  // noise model, iterations, threads
  // Data on an arbitrary scale: the thread and cloth fits fit a factor on
  // the model (a Lafortune model's coefficients carry any scale).
  bool fit_scale = false;
  // Thread and cloth candidates: the bounded model (ClothFitOptions::
  // energy_bound); the folds hold the whole table's bound.
  bool energy_bound = true;
  int folds = 5;  // k of the k-fold over rows, >= 2
  // Told "candidate i of n: NAME" as the fits go.
  std::function<void(const std::string&)> progress;
};

struct FabricSelection {
  ModelParams params;  // the chosen candidate's whole-table fit
  FitReport report;    // its report
  // Every candidate: free parameters, in-sample and held-out relative RMS,
  // BIC, the whole-table fit's seconds and whether it converged; `note`
  // names the parameters at a limit.
  SelectionReport selection;
};

// The entries a fold's fit holds at the whole-table fit's values (by
// name, for ClothFitOptions::fix or ThreadFitOptions::fix): the free ones
// that had no effect there (ParameterReport::no_effect: a zero Jacobian
// column, e.g. every entry of a thread of coverage 0, or the volume width
// of a thread without volume scattering) or that sit on a bound
// (ParameterReport::at_bound: a coverage, kd, albedo or diffuse at 0, kd
// at 1). The whole table did not determine them, or put them at the edge
// of their range; free on four fifths of the rows, they let a fold's fit
// leave the basin the whole table chose, and the held-out error then
// scores another model than the one written (CUReT rug b, plain weave
// with every freedom: whole table 0.235, held-out 0.267 with every entry
// free in the folds, 0.246 with these held; not in every basin: with free
// eta and a volume lobe 0.3 degrees wide, 0.187 held against 0.176 free,
// whole table 0.154). None when that would hold
// every free entry but the model's scale (which the fits free after their
// --fix): a fold would have nothing of the model to fit.
std::vector<std::string> HeldInFolds(const FitReport& whole);

// Throws InputError for a transmittance table or one with fewer rows than
// 2 * folds.
FabricSelection SelectFabricModel(const MeasurementTable& table,
                                  const FabricSelectOptions& options);

}  // namespace clothfit
