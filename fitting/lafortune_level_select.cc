#include "fitting/lafortune_level_select.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "fitting/lafortune_select_internal.h"

namespace clothfit {
namespace {

// Each level's models as ModelParams (what Evaluate takes), made once.
std::vector<std::vector<ModelParams>> LevelModels(const LafortuneMipResult& r) {
  std::vector<std::vector<ModelParams>> out(r.levels.size());
  for (size_t l = 0; l < r.levels.size(); ++l) {
    for (const LafortuneFitResult& t : r.levels[l].texels) {
      out[l].push_back(t.params);
    }
  }
  return out;
}

// Adds the errors of level l of r at the rows of fold `only` (all: < 0).
void AddLevelErrors(const LafortuneMipResult& r,
                    const std::vector<std::vector<ModelParams>>& models,
                    size_t l, const MeasurementTable& table,
                    const std::vector<int>& fold, int only, double* se,
                    double* ss, int* n) {
  AddFoldErrors(
      table, fold, only,
      [&](size_t i) -> const ModelParams* {
        const int g = LafortuneMipGroup(r, l, table.rows[i].s, table.rows[i].t);
        return g < 0 ? nullptr : &models[l][g];
      },
      se, ss, n);
}

}  // namespace

LafortuneLevelSelection SelectLafortuneLevelHeldOut(
    const MeasurementTable& table, const LafortuneMipOptions& options,
    int folds) {
  folds = std::clamp(folds, 2, 20);
  int lights = 0;
  const std::vector<int> fold = RequireLightFolds(table, folds, &lights);
  LafortuneLevelSelection out;
  // Progress over all folds + 1 fits (each the same texel jobs).
  auto progress_of = [&](int fit) -> std::function<void(int, int)> {
    if (!options.progress) return nullptr;
    return [&options, fit, folds](int done, int all) {
      options.progress(fit * all + done, (folds + 1) * all);
    };
  };
  LafortuneMipOptions all_rows = options;
  all_rows.progress = progress_of(0);
  out.mip = FitLafortuneMip(table, all_rows);
  const size_t levels = out.mip.levels.size();
  // Held-out errors per level, pooled over the folds.
  std::vector<double> hse(levels, 0.0), hss(levels, 0.0);
  std::vector<bool> usable(levels, true);
  for (int f = 0; f < folds; ++f) {
    LafortuneMipOptions o = options;
    o.progress = progress_of(f + 1);
    const LafortuneMipResult part =
        FitLafortuneMip(WithoutFold(table, fold, f), o);
    const std::vector<std::vector<ModelParams>> models = LevelModels(part);
    for (size_t l = 0; l < levels; ++l) {
      // A fold whose texel grid differs (its rows left a texel out) does
      // not score the level.
      if (l >= part.levels.size() ||
          part.levels[l].width != out.mip.levels[l].width ||
          part.levels[l].height != out.mip.levels[l].height) {
        usable[l] = false;
        continue;
      }
      for (const LafortuneFitResult& t : part.levels[l].texels) {
        usable[l] = usable[l] && t.report.usable;
      }
      AddLevelErrors(part, models, l, table, fold, f, &hse[l], &hss[l],
                     nullptr);
    }
  }
  const std::vector<std::vector<ModelParams>> models = LevelModels(out.mip);
  double best = HUGE_VAL;
  for (size_t l = 0; l < levels; ++l) {
    const LafortuneLevel& level = out.mip.levels[l];
    CandidateReport c;
    c.description = "level " + std::to_string(l) + " (" +
                    std::to_string(level.width) + " x " +
                    std::to_string(level.height) + ")";
    c.samples = -1;
    c.usable = usable[l];
    for (const LafortuneFitResult& t : level.texels) {
      c.usable = c.usable && t.report.usable;
      c.free_parameters +=
          table.channels *
          (1 + 4 * static_cast<int>(t.params.params.lobes.size()) +
           t.report.lut_views_fitted);
    }
    double se = 0.0, ss = 0.0;
    int n = 0;
    AddLevelErrors(out.mip, models, l, table, fold, -1, &se, &ss, &n);
    SetTrainingScores(se, ss, n, &c);
    c.heldout_relative_rms =
        c.usable && hss[l] > 0.0 ? std::sqrt(hse[l] / hss[l]) : -1.0;
    // The lowest held-out error; on a tie the finer level.
    if (c.usable && c.heldout_relative_rms >= 0.0 &&
        c.heldout_relative_rms < best) {
      best = c.heldout_relative_rms;
      out.report.chosen = static_cast<int>(l);
    }
    out.report.candidates.push_back(c);
  }
  out.level = out.report.chosen;
  char reason[200];
  if (out.level >= 0) {
    std::snprintf(reason, sizeof(reason),
                  "the lowest held-out relative rms (%d-fold over %d "
                  "lights); the levels finer than %d repeat its groups",
                  folds, lights, out.level);
  } else {
    std::snprintf(reason, sizeof(reason), "no level reached a usable fit");
  }
  out.report.reason = reason;
  // The finer levels take the chosen level's groups.
  for (int l = 0; l < out.level; ++l) {
    LafortuneLevel& level = out.mip.levels[l];
    for (int t = 0; t < level.height; ++t) {
      for (int s = 0; s < level.width; ++s) {
        // Level l's texel (s, t) covers level-0 texel (s << l, t << l).
        const int g = LafortuneMipGroup(out.mip, out.level, s << l, t << l);
        level.texels[t * level.width + s] = out.mip.levels[out.level].texels[g];
      }
    }
  }
  return out;
}

}  // namespace clothfit
