// Chooses the Lafortune model a table supports on held-out data: lobe count
// K in 0..3 and lookup table on or off, each candidate fitted k times
// without one fold of the table's lights and scored on the rows of that
// fold (k-fold cross-validation over lights, so that a candidate is judged
// at light directions it never saw). The candidate with the lowest pooled
// held-out relative RMS error is chosen; each candidate's BIC on all rows
// is reported beside it (docs/lafortune.md).
#pragma once

#include "fitting/lafortune_mip.h"
#include "fitting/model_selection.h"

namespace clothfit {

struct LafortuneSelection {
  LafortuneFitResult fit;  // the chosen candidate fitted on all rows
  SelectionReport report;
};

// For a table without texel columns. A lookup-table candidate is left out
// when no view has enough rows for an entry of its own (it is then the
// candidate without one). Throws InputError when the table has fewer
// distinct lights than folds (folds in [2, 20]).
LafortuneSelection SelectLafortuneHeldOut(const MeasurementTable& table,
                                          const LafortuneMipOptions& options,
                                          int folds);

}  // namespace clothfit
