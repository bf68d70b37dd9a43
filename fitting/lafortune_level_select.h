// Chooses the mip level a texel table supports on held-out data (Daubert
// et al. 2001, Section 5.1: level l + 1 pools the samples of 2 x 2 groups
// of level l): the mip fit (fitting/lafortune_mip.h) is repeated k times
// without one fold of the table's lights, and each level is scored on the
// rows of that fold, a row judged by the model of the group its texel
// joins at that level. A level finer than the data support fits each
// texel's few samples and loses on lights it never saw; the coarsest
// levels average away real variation. The level with the lowest pooled
// held-out relative RMS is chosen; the map is fitted on all rows and every
// level finer than the chosen one takes, at each texel, the model of the
// group the texel joins at the chosen level, so that the map keeps its
// size and texel coordinates (docs/lafortune.md).
#pragma once

#include "fitting/lafortune_mip.h"
#include "fitting/model_selection.h"

namespace clothfit {

struct LafortuneLevelSelection {
  LafortuneMipResult mip;  // fitted on all rows, finer levels replaced
  SelectionReport report;  // a candidate per level, in level order
  int level = -1;          // the chosen level (report.chosen)
};

// For a table with s,t columns; the lobe count and lookup table are those
// of `options` (options.mip is taken as set). Throws InputError when the
// table has fewer distinct lights than folds (folds in [2, 20]).
LafortuneLevelSelection SelectLafortuneLevelHeldOut(
    const MeasurementTable& table, const LafortuneMipOptions& options,
    int folds);

}  // namespace clothfit
