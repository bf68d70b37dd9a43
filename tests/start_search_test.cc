// The grid search of the thread and cloth starts (fitting/start_search.h):
// on a table the model reproduces exactly, with the widths on the search's
// grid, the search returns the truth, its linear entries (albedo, kd,
// scale) solved exactly also where a bound is active (kd = 0 or 1: the
// active-set solve, not the unconstrained one).
#include "fitting/start_search.h"

#include <gtest/gtest.h>

#include <cmath>

#include "fit_test_util.h"
#include "models/evaluate.h"

namespace clothfit {
namespace {

struct Case {
  double kd, albedo, scale;
};

// The search of one thread's starts on `table` (which with `weighting`
// must outlive it) from `init`: kd, albedo and the scale free, the widths
// searched when `widths_free`.
StartSearchProblem ThreadSearch(const MeasurementTable& table,
                                const Weighting& weighting,
                                const ThreadParams& init, bool widths_free) {
  StartSearchProblem search;
  search.table = &table;
  search.weighting = &weighting;
  search.init = {init};
  search.contribution = [&table](size_t, const ThreadParams& p) {
    RowValues v(table.rows.size());
    for (size_t i = 0; i < v.size(); ++i) {
      v[i] = Value(p, table.rows[i].wi, table.rows[i].wo, table.quantity);
    }
    return v;
  };
  search.kd_free = {true};
  search.gamma_s_free = {widths_free};
  search.gamma_v_free = {widths_free};
  search.albedo_free = {true};
  search.fit_scale = true;
  return search;
}

class StartSearchExact : public ::testing::TestWithParam<Case> {};

TEST_P(StartSearchExact, RecoversLinearEntriesAtTheirBoundsToo) {
  const Case c = GetParam();
  ThreadParams truth;
  truth.eta = 1.46;
  truth.kd = c.kd;
  truth.gamma_s_deg = 8.0;   // on the grid 1, 1.41, 2, ..., 90 degrees
  truth.gamma_v_deg = 16.0;  // likewise
  truth.albedo = glm::dvec3(c.albedo);
  MeasurementTable table = testing_util::NoisyTable(truth, 0.0, 11, 300);
  for (TableRow& row : table.rows) row.value *= c.scale;  // another unit
  const Weighting weighting(table, NoiseModel());

  ThreadParams init = truth;  // eta is not searched; the rest is
  init.kd = 0.5;
  init.gamma_s_deg = 3.0;
  init.gamma_v_deg = 30.0;
  init.albedo = glm::dvec3(0.1);
  const StartSearchProblem search = ThreadSearch(table, weighting, init, true);

  const std::vector<StartPoint> starts = SearchStarts(search, 1);
  ASSERT_EQ(starts.size(), 1u);
  const StartPoint& best = starts[0];
  const ThreadParams& p = best.threads[0];
  EXPECT_DOUBLE_EQ(p.gamma_s_deg, 8.0);
  // At kd = 1 the volume lobe is all isotropic: gamma_v has no effect.
  if (c.kd < 1.0) {
    EXPECT_DOUBLE_EQ(p.gamma_v_deg, 16.0);
  }
  // The surface term carries no albedo, so it pins the scale.
  EXPECT_NEAR(p.kd, c.kd, 1e-9);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(p.albedo[k], c.albedo, 1e-9);
  EXPECT_NEAR(best.scale, c.scale, 1e-9 * c.scale);
  // The cost from the Gram sums, |y|^2 - 2 b.x + x.G.x, keeps their
  // rounding (~1e-12 here); a wrong solution costs O(1) or more.
  EXPECT_LT(best.cost, 1e-9);
}

// Data the model fits best with kd < 0 (the model is linear in kd, so
// kd = -0.1 is a valid table): the unconstrained solution leaves the
// bounds, the search must return the bounded optimum, kd = 0 exactly, and
// a cost no higher than that of the feasible truth-like point (kd = 0 with
// the data's albedo and scale).
TEST(StartSearchBounds, KdBelowZeroGivesTheBoundedOptimum) {
  ThreadParams truth;
  truth.kd = 0.0;
  truth.gamma_s_deg = 8.0;
  truth.gamma_v_deg = 16.0;
  truth.albedo = glm::dvec3(0.4);
  MeasurementTable table = testing_util::NoisyTable(truth, 0.0, 13, 300);
  ThreadParams beyond = truth;
  beyond.kd = -0.1;
  for (TableRow& row : table.rows) {
    row.value = 2.0 * Value(beyond, row.wi, row.wo, table.quantity);
  }
  const Weighting weighting(table, NoiseModel());
  ThreadParams init = truth;  // widths fixed at the truth's
  init.kd = 0.5;
  init.albedo = glm::dvec3(0.1);
  const StartSearchProblem search = ThreadSearch(table, weighting, init, false);
  const std::vector<StartPoint> starts = SearchStarts(search, 1);
  ASSERT_EQ(starts.size(), 1u);
  EXPECT_EQ(starts[0].threads[0].kd, 0.0);
  // With kd = 0 the model is s surface + (s A) P, P the volume lobe of unit
  // albedo: the bounded optimum's s and A by the 2 x 2 normal equations,
  // computed here from the rows.
  ThreadParams bare = truth, unit = truth;
  bare.albedo = glm::dvec3(0.0);
  unit.albedo = glm::dvec3(1.0);
  double g00 = 0, g01 = 0, g11 = 0, b0 = 0, b1 = 0;
  for (const TableRow& row : table.rows) {
    const glm::dvec3 w = weighting.InverseVariance(row, 1.0);
    const glm::dvec3 surface = Value(bare, row.wi, row.wo, table.quantity);
    const glm::dvec3 volume =
        Value(unit, row.wi, row.wo, table.quantity) - surface;
    for (int c = 0; c < table.channels; ++c) {
      g00 += w[c] * surface[c] * surface[c];
      g01 += w[c] * surface[c] * volume[c];
      g11 += w[c] * volume[c] * volume[c];
      b0 += w[c] * surface[c] * row.value[c];
      b1 += w[c] * volume[c] * row.value[c];
    }
  }
  const double det = g00 * g11 - g01 * g01;
  const double scale = (b0 * g11 - b1 * g01) / det;
  const double albedo = (g00 * b1 - g01 * b0) / det / scale;
  ASSERT_GT(scale, 0.0);
  ASSERT_GT(albedo, 0.0);
  EXPECT_NEAR(starts[0].scale, scale, 1e-9 * scale);
  EXPECT_NEAR(starts[0].threads[0].albedo.x, albedo, 1e-9 * albedo);
}

INSTANTIATE_TEST_SUITE_P(
    Kd, StartSearchExact,
    ::testing::Values(Case{0.3, 0.4, 1.0},    // inside the bounds
                      Case{0.0, 0.4, 2.5},    // kd at 0: B on its bound
                      Case{1.0, 0.25, 0.5}),  // kd at 1: U on its bound
    [](const auto& info) {
      return std::string(info.index == 0   ? "Inside"
                         : info.index == 1 ? "KdZero"
                                           : "KdOne");
    });

}  // namespace
}  // namespace clothfit
