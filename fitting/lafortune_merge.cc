#include "fitting/lafortune_merge.h"

#include <chrono>
#include <memory>
#include <utility>
#include <vector>

#include "fitting/lafortune_samples.h"
#include "io/input_error.h"
#include "models/mip_levels.h"

namespace clothfit {

bool WeightingIsPerRow(const NoiseModel& noise) {
  return noise.kind != NoiseKind::kRelative || noise.floor > 0.0;
}

namespace {

// A level above the blocks while it is fitted: each group's samples, its
// candidate fits (in LafortuneCandidateLobes' order), and their errors.
struct UpperLevel {
  int width = 0, height = 0;
  std::vector<int> group_x, group_y;  // level-0 column/row -> group's
  std::vector<SampleCollector> collectors;
  std::vector<std::vector<LafortuneFitResult>> candidates;
  std::vector<std::vector<LafortuneErrorSums>> errors;
};

}  // namespace

void FitLafortuneUpperLevels(const MeasurementTable& directions, int width,
                             int height, const LafortuneRowStream& stream,
                             const LafortuneMipOptions& options,
                             size_t first_level, LafortuneMipResult* result) {
  const auto start = std::chrono::steady_clock::now();
  if (!WeightingIsPerRow(options.noise)) {
    throw InputError(
        "a texture fitted in blocks needs a weighting of each row by itself: "
        "relative noise needs a floor (--noise-floor)");
  }
  const ViewIndex views(directions);
  const Weighting weighting = LafortuneWeighting(directions, options.noise);
  result->views = views.views();
  const size_t levels = options.mip ? MipLevelCount(width, height) : 1;
  // Every level holds every row; the fits count every texel.
  const size_t rows = directions.rows.size() * static_cast<size_t>(width) *
                      static_cast<size_t>(height);
  result->fits = 0;
  for (size_t l = 0; l < first_level; ++l) {
    result->levels[l].samples = rows;
    result->fits += static_cast<int>(result->levels[l].texels.size());
  }
  if (first_level >= levels) return;
  result->levels.resize(levels);
  std::vector<UpperLevel> upper(levels - first_level);
  for (size_t u = 0; u < upper.size(); ++u) {
    const int l = static_cast<int>(first_level + u);
    UpperLevel& level = upper[u];
    level.width = MipLevelSize(width, l);
    level.height = MipLevelSize(height, l);
    // Level 0 -> level l through each level's parent (ROUND_DOWN), as
    // FitLafortuneMip pools them.
    for (int x = 0; x < width; ++x) {
      int g = x;
      for (int k = 1; k <= l; ++k) g = MipParent(g, MipLevelSize(width, k));
      level.group_x.push_back(g);
    }
    for (int y = 0; y < height; ++y) {
      int g = y;
      for (int k = 1; k <= l; ++k) g = MipParent(g, MipLevelSize(height, k));
      level.group_y.push_back(g);
    }
    const size_t groups = static_cast<size_t>(level.width) * level.height;
    level.collectors.reserve(groups);
    for (size_t g = 0; g < groups; ++g) {
      level.collectors.emplace_back(directions, views);
    }
    level.candidates.resize(groups);
  }
  auto group_of = [](const UpperLevel& level, const TableRow& row) {
    return static_cast<size_t>(level.group_y[row.t]) * level.width +
           level.group_x[row.s];
  };
  // One pass: the samples of every group of every level above the blocks.
  stream([&](size_t image, const TableRow& row) {
    const int view = views.RowView(image), pair = views.RowPair(image);
    for (UpperLevel& level : upper) {
      level.collectors[group_of(level, row)].Add(row, view, pair, weighting);
    }
  });
  // The errors of the candidates of `pending` levels (indices into upper),
  // in one pass; then each group's choice.
  auto choose = [&](const std::vector<size_t>& pending) {
    for (size_t u : pending) {
      UpperLevel& level = upper[u];
      level.errors.resize(level.candidates.size());
      for (size_t g = 0; g < level.candidates.size(); ++g) {
        for (const LafortuneFitResult& fit : level.candidates[g]) {
          level.errors[g].emplace_back(fit.params, directions, views);
        }
      }
    }
    stream([&](size_t image, const TableRow& row) {
      const int view = views.RowView(image);
      for (size_t u : pending) {
        UpperLevel& level = upper[u];
        for (LafortuneErrorSums& sums : level.errors[group_of(level, row)]) {
          sums.Add(row, view);
        }
      }
    });
    for (size_t u : pending) {
      UpperLevel& level = upper[u];
      LafortuneLevel& out = result->levels[first_level + u];
      for (size_t g = 0; g < level.candidates.size(); ++g) {
        LafortuneCandidates chosen(options.tolerance);
        for (size_t c = 0; c < level.candidates[g].size(); ++c) {
          LafortuneFitResult& fit = level.candidates[g][c];
          level.errors[g][c].Finish(&fit.report.rms, &fit.report.relative_rms,
                                    &fit.report.view_relative_rms);
          if (chosen.Offer(std::move(fit))) break;
        }
        out.texels[g] = chosen.Take();
      }
      level.errors.clear();
      level.candidates.clear();
    }
  };
  std::vector<size_t> deferred;
  for (size_t u = 0; u < upper.size(); ++u) {
    const auto t0 = std::chrono::steady_clock::now();
    const size_t l = first_level + u;
    UpperLevel& level = upper[u];
    LafortuneLevel& out = result->levels[l];
    out.width = level.width;
    out.height = level.height;
    out.samples = rows;
    const size_t groups = level.collectors.size();
    out.texels.resize(groups);
    const std::vector<std::vector<const LafortuneModel*>> children =
        LafortuneChildren(result->levels[l - 1], level.width, level.height);
    RunTexelJobs(groups, options.threads, [&](size_t g) {
      int skipped = 0;
      const TexelSamples samples = level.collectors[g].Finish(&skipped);
      LafortuneMipOptions texel_options = options;
      texel_options.fit.warm_starts = children[g];
      // Every lobe count the choice may take: without a tolerance one; with
      // one, those after the chosen are fitted in vain.
      for (int k : LafortuneCandidateLobes(options)) {
        level.candidates[g].push_back(
            FitLafortuneCandidate(samples, k, skipped, texel_options));
      }
    });
    level.collectors.clear();
    deferred.push_back(u);
    // The next level starts from this one's choice: with a tolerance the
    // errors choose it; else it is the one candidate, errors later.
    if (options.tolerance > 0.0) {
      choose(deferred);
      deferred.clear();
    } else {
      for (size_t g = 0; g < groups; ++g) {
        out.texels[g].params = level.candidates[g].front().params;
      }
    }
    out.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0)
            .count();
    result->fits += static_cast<int>(groups);
  }
  if (!deferred.empty()) choose(deferred);
  result->seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
}

}  // namespace clothfit
