#include "fitting/lafortune_select.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "fitting/lafortune_select_internal.h"
#include "models/evaluate.h"

namespace clothfit {
namespace {

// The first lobe of p whose N sits at its lower search limit in some
// channel ("lobes[1]"), or "": a lobe that collapsed to a near-constant
// (|C|^N flat over the hemisphere), so that the model is the one with a
// lobe fewer in disguise.
std::string CollapsedLobe(const LafortuneParams& p) {
  const double middle = 0.5 * (kLafortuneN.fit_lo + kLafortuneN.fit_hi);
  for (const LafortuneLimit& limit : LafortuneAtSearchLimit(p)) {
    // "lobes[K].N_c" at its lower limit.
    const size_t dot = limit.name.find('.');
    if (limit.name.compare(dot + 1, 2, "N_") == 0 && limit.value < middle) {
      return limit.name.substr(0, dot);
    }
  }
  return "";
}

}  // namespace

LafortuneSelection SelectLafortuneHeldOut(const MeasurementTable& table,
                                          const LafortuneMipOptions& options,
                                          int folds) {
  folds = std::clamp(folds, 2, 20);
  int lights = 0;
  const std::vector<int> fold = RequireLightFolds(table, folds, &lights);
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
      c.samples = -1;  // no tangent samples
      c.usable = all.report.usable;
      // A candidate whose lobe collapsed is the one with a lobe fewer in
      // disguise (tried before it): scored, not chosen.
      const std::string collapsed = CollapsedLobe(all.params.params);
      if (!collapsed.empty()) {
        char note[96];
        std::snprintf(note, sizeof(note),
                      "%s collapsed to N = %g, a near-constant: not chosen",
                      collapsed.c_str(), kLafortuneN.fit_lo);
        c.note = note;
      }
      const ModelParams all_params = all.params;
      double se = 0.0, ss = 0.0;
      int n = 0;
      AddFoldErrors(
          table, fold, -1, [&](size_t) { return &all_params; }, &se, &ss, &n);
      SetTrainingScores(se, ss, n, &c);
      double hse = 0.0, hss = 0.0;
      for (int f = 0; f < folds && c.usable; ++f) {
        const LafortuneFitResult part =
            FitLafortuneTable(WithoutFold(table, fold, f), o);
        c.usable = part.report.usable;
        const ModelParams part_params = part.params;
        AddFoldErrors(
            table, fold, f, [&](size_t) { return &part_params; }, &hse, &hss,
            nullptr);
      }
      c.heldout_relative_rms =
          c.usable && hss > 0.0 ? std::sqrt(hse / hss) : -1.0;
      // The lowest held-out error; on a tie the candidate tried first (fewer
      // lobes, no table).
      if (c.usable && collapsed.empty() && c.heldout_relative_rms >= 0.0 &&
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
