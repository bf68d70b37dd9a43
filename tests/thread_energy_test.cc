// Fits of the bounded thread (models/bounded.h, the default of FitThread):
// they reach the bounded model's optimum and recover the thread, from
// small tables and from large ones, whose start is fitted to a sample.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "fitting/least_squares.h"
#include "fitting/thread_fit.h"
#include "models/bounded.h"
#include "models/evaluate.h"
#include "models/presets.h"
#include "tests/fit_test_util.h"

namespace clothfit {
namespace {

// The satin preset's warp thread with its energy bound (the bounded
// model a table is drawn from).
ThreadParams BoundedSatinThread() {
  ClothParams satin;
  if (!GetPreset("polyester_satin_charmeuse", &satin)) {
    ADD_FAILURE() << "no preset polyester_satin_charmeuse";
    return ThreadParams();
  }
  ThreadParams thread = satin.threads[0].params;
  thread.energy_bound = EnergyBoundOf(thread);
  return thread;
}

// The bounded fit reaches the bounded model's optimum, not a point where
// the rows' bound factors, held fixed, would have it: on a table of the
// bounded satin thread with 3 % noise (the bound lowers most rows toward
// grazing), moving any parameter 0.5 % either way from the fit does not
// lower the sum of squares (absolute noise) of the bounded model, its
// bound found afresh at each point.
TEST(ThreadEnergy, BoundedFitIsAtTheBoundedModelsOptimum) {
  const ThreadParams truth = BoundedSatinThread();
  const MeasurementTable table = testing_util::NoisyTable(truth, 0.03, 5, 600);
  ThreadFitOptions options;
  options.energy_bound = true;
  options.solver.noise.kind = NoiseKind::kAbsolute;
  const ThreadFitResult fit = FitThread(table, options);
  ASSERT_TRUE(fit.report.usable) << fit.report.message;
  EXPECT_TRUE(fit.report.converged) << fit.report.message;
  auto squares = [&](const std::vector<double>& x) {
    ThreadParams p;
    FromArray(x.data(), &p);
    return testing_util::BoundedSquares(p, table);
  };
  std::vector<double> x(kThreadFlatSize);
  ToArray(fit.params, x.data());
  const double best = squares(x);
  for (int i = 0; i < kThreadFlatSize; ++i) {
    for (double step : {1.005, 1.0 / 1.005}) {
      std::vector<double> moved = x;
      moved[i] *= step;
      EXPECT_LE(best, squares(moved) * (1.0 + 1e-9)) << i << " " << step;
    }
  }
}

// A bounded thread fit recovers the satin's thread from a table of the
// bounded thread with 2 % noise, from the default start: the first fit on
// the rows within 60 degrees, then the refits through the bound. Every
// parameter within 5 % of the truth, the bound attached, energy conserved.
TEST(ThreadEnergy, BoundedFitRecoversTheThreadFromNoisyData) {
  const ThreadParams truth = BoundedSatinThread();
  ASSERT_NE(truth.energy_bound, nullptr);
  const MeasurementTable table =
      testing_util::NoisyTable(truth, 0.02, 11, 2000);
  ThreadFitOptions options;
  options.energy_bound = true;
  const ThreadFitResult fit = FitThread(table, options);
  ASSERT_TRUE(fit.report.usable) << fit.report.message;
  EXPECT_TRUE(fit.report.converged) << fit.report.message;
  ASSERT_NE(fit.params.energy_bound, nullptr);
  EXPECT_LE(fit.report.max_albedo, 1.0);
  std::vector<double> got(kThreadFlatSize), want(kThreadFlatSize);
  ToArray(fit.params, got.data());
  ToArray(truth, want.data());
  for (int i = 0; i < kThreadFlatSize; ++i) {
    EXPECT_NEAR(got[i], want[i], 0.05 * std::abs(want[i]) + 1e-3) << i;
  }
}

// A table of more than kSampleRows rows: the start (the paper's model
// fitted to some rows) is fitted to its sample, and the bounded solves
// refine on every row. On 30,000 rows of the bounded satin thread with 2 %
// noise (and its sigma column), the fit is of every row (its residuals
// and rows), converged, at the bounded model's optimum over every row
// (0.2 % steps of any parameter do not lower its sum of squared
// residuals over sigma) and within 3 reported sigmas (and 1 %) of the
// truth.
TEST(ThreadEnergy, LargeTableStartsFromItsSampleAndIsFittedOnEveryRow) {
  const ThreadParams truth = BoundedSatinThread();
  const int rows = 30000;
  ASSERT_GT(static_cast<size_t>(rows), kSampleRows);
  const MeasurementTable table =
      testing_util::NoisyTable(truth, 0.02, 17, rows);
  ThreadFitOptions options;
  const ThreadFitResult fit = FitThread(table, options);
  ASSERT_TRUE(fit.report.usable) << fit.report.message;
  EXPECT_TRUE(fit.report.converged) << fit.report.message;
  EXPECT_EQ(fit.report.rows, rows);
  EXPECT_EQ(fit.report.residuals, 3 * rows);
  ASSERT_NE(fit.params.energy_bound, nullptr);
  EXPECT_LE(fit.report.max_albedo, 1.0);
  std::vector<double> x(kThreadFlatSize), want(kThreadFlatSize);
  ToArray(fit.params, x.data());
  ToArray(truth, want.data());
  auto squares = [&](const std::vector<double>& at) {
    ThreadParams p;
    FromArray(at.data(), &p);
    return testing_util::BoundedSquares(p, table, true);
  };
  const double best = squares(x);
  for (int i = 0; i < kThreadFlatSize; ++i) {
    const ParameterReport& p = fit.report.parameters[i];
    EXPECT_LE(std::abs(x[i] - want[i]), 3.0 * p.stddev) << p.name;
    EXPECT_NEAR(x[i], want[i], 0.01 * std::abs(want[i])) << p.name;
    for (double step : {1.002, 1.0 / 1.002}) {
      std::vector<double> moved = x;
      moved[i] *= step;
      EXPECT_LE(best, squares(moved) * (1.0 + 1e-9)) << p.name << " " << step;
    }
  }
}

// A table whose every row lies in the bound's fade to the horizon (the
// light within 3 degrees of it): the start cannot leave those rows out,
// and is fitted to all of them. The fit is usable, finite, bounded and
// reproduces the table's noise-free values of the bounded thread.
TEST(ThreadEnergy, TableOfGrazingLightOnlyIsFittedOnItsRows) {
  ThreadParams truth;  // the default thread (Linen Plain's)
  truth.energy_bound = EnergyBoundOf(truth);
  MeasurementTable table = testing_util::NoisyTable(truth, 0.0, 3, 300);
  const double sin88 = std::sin(88.5 * kPi / 180.0);
  const double cos88 = std::cos(88.5 * kPi / 180.0);
  ASSERT_LT(cos88, kEnergyBoundFadeCos);
  for (TableRow& row : table.rows) {
    const double phi = std::atan2(row.wi.y, row.wi.x);
    row.wi = glm::dvec3(sin88 * std::cos(phi), sin88 * std::sin(phi), cos88);
    row.value = Evaluate(ModelParams(truth), row.wi, row.wo, table.quantity);
  }
  const ThreadFitResult fit = FitThread(table, ThreadFitOptions());
  ASSERT_TRUE(fit.report.usable) << fit.report.message;
  EXPECT_EQ(fit.report.rows, 300);
  ASSERT_NE(fit.params.energy_bound, nullptr);
  EXPECT_LE(fit.report.max_albedo, 1.0);
  std::vector<double> x(kThreadFlatSize);
  ToArray(fit.params, x.data());
  for (double v : x) EXPECT_TRUE(std::isfinite(v));
  EXPECT_LT(fit.report.relative_rms, 0.05);
}

}  // namespace
}  // namespace clothfit
