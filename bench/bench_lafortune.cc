#include <algorithm>
#include <map>

#include "bench/bench_internal.h"
#include "data_synthetic/virtual_gonio.h"
#include "fitting/lafortune_mip.h"

namespace clothfit {
namespace bench_internal {
namespace {

// Lafortune: virtual-gonio plain weave; every 4th light held out. Knobs:
// lobes K, the lookup table, the solver tolerance, threads, mip levels,
// and the solve of lobes and table: joint (the default) against the
// paper's alternation, side by side in the same run.
// The SciPy peer on the same train/test split: one row per lobe count, its
// time the script's own (the fits, not Python's start or the CSV parsing),
// CPU = wall (one thread). Returns why it did not run, or "".
// The held-out rows of each level-0 texel (s, t) of a gonio table.
using TexelRows = std::map<std::pair<int, int>, std::vector<size_t>>;

// The error of mip level `l` of a fit: for each texel (group) of the level,
// the relative RMS of its model at the held-out rows of all the level-0
// texels it pools (LafortuneMipGroup: the group a level-0 texel joins as
// FitLafortuneMip pools them); the mean over the level's texels.
// *usable: every texel of the level fitted.
double LevelError(const LafortuneMipResult& r, size_t l,
                  const MeasurementTable& test, const ViewIndex& test_views,
                  const TexelRows& test_rows, bool* usable) {
  const LafortuneLevel& level = r.levels[l];
  std::vector<std::vector<size_t>> pooled(level.texels.size());
  for (const auto& [texel, indices] : test_rows) {
    const int g = LafortuneMipGroup(r, l, texel.first, texel.second);
    if (g < 0) continue;
    std::vector<size_t>& to = pooled[g];
    to.insert(to.end(), indices.begin(), indices.end());
  }
  *usable = true;
  double sum = 0.0;
  int n = 0;
  for (size_t i = 0; i < level.texels.size(); ++i) {
    *usable = *usable && level.texels[i].report.usable;
    double rms = 0.0, rel = 0.0;
    LafortuneErrors(level.texels[i].params, test, test_views, pooled[i], &rms,
                    &rel);
    sum += rel;
    ++n;
  }
  return n ? sum / n : kNaN;
}

// Model size over mip levels: the default fit with all levels, timed
// (o.repeats runs) level by level; per level a row of the model
// "lafortune_mip" with its time, its error against the held-out rows
// (LevelError) and its size = texels of the level.
void BenchMipLevels(const BenchOptions& o, const MeasurementTable& train,
                    const MeasurementTable& test, const ViewIndex& test_views,
                    const TexelRows& test_rows, std::vector<BenchRow>* rows) {
  Say(o, "lafortune: mip levels");
  LafortuneMipOptions fit;
  fit.mip = true;
  std::vector<std::vector<double>> seconds;  // [level][run]
  LafortuneMipResult r;
  for (int run = 0; run < std::max(1, o.repeats); ++run) {
    r = FitLafortuneMip(train, fit);
    seconds.resize(r.levels.size());
    for (size_t l = 0; l < r.levels.size(); ++l) {
      seconds[l].push_back(r.levels[l].seconds);
    }
  }
  for (size_t l = 0; l < r.levels.size(); ++l) {
    const LafortuneLevel& level = r.levels[l];
    BenchRow row;
    row.model = "lafortune_mip";
    row.config = "level=" + std::to_string(l) + " (" +
                 std::to_string(level.width) + " x " +
                 std::to_string(level.height) + ")";
    row.label = "level " + std::to_string(l);
    row.group = "lobes=2 lut=on";
    row.repeats = static_cast<int>(seconds[l].size());
    row.wall_median_s = Median(seconds[l]);
    row.wall_min_s = *std::min_element(seconds[l].begin(), seconds[l].end());
    row.wall_max_s = *std::max_element(seconds[l].begin(), seconds[l].end());
    row.cpu_median_s = kNaN;  // the level's share is not measured
    row.peak_mb = kNaN;
    row.value_error =
        LevelError(r, l, test, test_views, test_rows, &row.success);
    row.param_error = kNaN;
    row.size = static_cast<double>(level.texels.size());
    row.is_default = l == 0;
    rows->push_back(row);
  }
}

}  // namespace

std::string BenchLafortune(const BenchOptions& o, std::vector<BenchRow>* rows) {
  VirtualGonioOptions gonio;
  gonio.texels = o.quick ? 2 : 8;
  gonio.directions = o.quick ? 4 : 8;
  gonio.seed = o.seed;
  const MeasurementTable all = MeasureVirtualGonio(gonio);
  // Rows are ordered texel, view, light: the light index is the row index
  // modulo the number of lights.
  const size_t lights =
      static_cast<size_t>(gonio.directions) * gonio.directions;
  MeasurementTable train = all, test = all;
  train.rows.clear();
  test.rows.clear();
  for (size_t i = 0; i < all.rows.size(); ++i) {
    (i % lights % 4 == 3 ? test : train).rows.push_back(all.rows[i]);
  }
  const ViewIndex test_views(test);
  TexelRows test_rows;
  for (size_t i = 0; i < test.rows.size(); ++i) {
    test_rows[{test.rows[i].s, test.rows[i].t}].push_back(i);
  }
  // Level 0's error: the mean over texels of the relative RMS at their
  // held-out rows.
  auto run = [&](const LafortuneMipOptions& fit) {
    const LafortuneMipResult r = FitLafortuneMip(train, fit);
    Outcome out;
    out.value_error =
        LevelError(r, 0, test, test_views, test_rows, &out.success);
    return out;
  };
  struct Knobs {
    int lobes;
    bool lut;
    int ftol_exp;
    int threads;
    bool mip;
    LafortuneSolve solve = LafortuneSolve::kJoint;
  };
  std::vector<Knobs> knobs;
  for (int k :
       o.quick ? std::vector<int>{0, 2} : std::vector<int>{0, 1, 2, 3}) {
    for (bool lut : {false, true}) {
      for (int e : o.quick ? std::vector<int>{5} : std::vector<int>{4, 5, 6}) {
        knobs.push_back({k, lut, e, 0, false});
      }
    }
  }
  // The paper's alternation beside the default joint solve (Daubert et
  // al. 2001, Section 5).
  knobs.push_back({2, true, 5, 0, false, LafortuneSolve::kAlternate});
  if (!o.quick) {
    knobs.push_back({2, true, 5, 1, false});
    knobs.push_back({2, true, 5, 0, true});
    knobs.push_back({2, true, 5, 0, true, LafortuneSolve::kAlternate});
  }
  for (const Knobs& k : knobs) {
    std::ostringstream config;
    config << "lobes=" << k.lobes << " lut=" << (k.lut ? "on" : "off")
           << " tolerance=1e-" << k.ftol_exp << " threads="
           << (k.threads == 0 ? std::string("all") : std::to_string(k.threads))
           << " mip=" << (k.mip ? "on" : "off") << " solve="
           << (k.solve == LafortuneSolve::kJoint ? "joint" : "alternate");
    Say(o, "lafortune: " + config.str());
    LafortuneMipOptions fit;
    fit.fit.lobes = k.lobes;
    fit.fit.lookup_table = k.lut;
    fit.fit.function_tolerance = std::pow(10.0, -k.ftol_exp);
    fit.threads = k.threads;
    fit.mip = k.mip;
    fit.fit.solve = k.solve;
    const bool joint = k.solve == LafortuneSolve::kJoint;
    BenchRow row = Measure(o, [&]() { return run(fit); });
    row.model = "lafortune";
    row.config = config.str();
    row.group = std::string("lut=") + (k.lut ? "on" : "off") +
                (joint ? "" : " solve=alternate");
    if (k.ftol_exp == 5 && k.threads == 0 && !k.mip && joint) {
      row.size = k.lobes;
    }
    row.is_default = k.lobes == 2 && k.lut && k.ftol_exp == 5 &&
                     k.threads == 0 && !k.mip && joint;
    rows->push_back(row);
  }
  SweepLinearSolvers(
      o, "lafortune",
      [&](LinearSolver solver) {
        LafortuneMipOptions fit;
        fit.mip = false;
        fit.fit.linear_solver = solver;
        return run(fit);
      },
      rows);
  BenchMipLevels(o, train, test, test_views, test_rows, rows);
  return RunPeer(o, train, test,
                 o.quick ? std::vector<int>{2} : std::vector<int>{1, 2}, rows);
}

}  // namespace bench_internal
}  // namespace clothfit
