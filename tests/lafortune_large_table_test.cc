// Lafortune fits of large tables of random directions (one view a row):
// the per-table index of views, lights and pairs, the fit without a lookup
// table that keeps no per-view arrays, and the lobe solve over compressed
// chunks of samples (fitting/lafortune_lobes.cc) beyond
// LafortuneFitOptions::max_one_block_samples.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "fitting/lafortune_fit.h"
#include "fitting/lafortune_mip.h"
#include "io/table.h"
#include "models/lafortune.h"

namespace clothfit {
namespace {

glm::dvec3 Direction(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double z = std::sqrt(u(rng));  // cosine-distributed
  const double r = std::sqrt(1.0 - z * z), phi = 2.0 * kPi * u(rng);
  return {r * std::cos(phi), r * std::sin(phi), z};
}

// A one-lobe model whose largest directional albedo is below 1.
LafortuneModel Truth() {
  LafortuneModel m;
  m.params.diffuse = {0.08, 0.06, 0.05};
  LafortuneLobe lobe;
  lobe.cx = {-0.8, -0.75, -0.7};
  lobe.cy = {-0.8, -0.85, -0.9};
  lobe.cz = {0.9, 0.95, 1.0};
  lobe.n = {6.0, 9.0, 12.0};
  m.params.lobes = {lobe};
  return m;
}

// `rows` rows of the model at random light and view directions
// (cosine-weighted values, no sigma column).
MeasurementTable RandomTable(const LafortuneModel& m, size_t rows,
                             uint64_t seed) {
  std::mt19937_64 rng(seed);
  MeasurementTable t;
  t.quantity = Quantity::kCosineWeighted;
  for (size_t i = 0; i < rows; ++i) {
    TableRow row;
    row.wi = Direction(rng);
    row.wo = Direction(rng);
    row.value = LafortuneRho(m, row.wi, row.wo);
    row.source_line = static_cast<int>(i) + 2;
    t.rows.push_back(row);
  }
  return t;
}

TEST(LafortuneLargeTable, ViewIndexNumbersKeysInOrderOfFirstAppearance) {
  const glm::dvec3 a = glm::normalize(glm::dvec3(0.1, 0.2, 0.9));
  const glm::dvec3 b = glm::normalize(glm::dvec3(-0.3, 0.1, 0.8));
  const glm::dvec3 c(0.0, 0.0, 1.0);
  // (light, view) per row; a + 1e-12 rounds to a's key (equal to 1e-9).
  const glm::dvec3 a_near = a + glm::dvec3(1e-12, 0.0, 0.0);
  const std::vector<std::pair<glm::dvec3, glm::dvec3>> pairs = {
      {a, b}, {b, b}, {a, c}, {a_near, b}, {c, a}, {b, c}, {a, b}};
  MeasurementTable t;
  for (const auto& [wi, wo] : pairs) {
    TableRow row;
    row.wi = wi;
    row.wo = wo;
    t.rows.push_back(row);
  }
  const ViewIndex index(t);
  ASSERT_EQ(index.views().size(), 3u);  // b, c, a in order of appearance
  EXPECT_EQ(index.views()[0], b);
  EXPECT_EQ(index.views()[1], c);
  EXPECT_EQ(index.views()[2], a);
  const std::vector<int> view = {0, 0, 1, 0, 2, 1, 0};
  const std::vector<int> light = {0, 1, 0, 0, 2, 1, 0};
  const std::vector<int> pair = {0, 1, 2, 0, 3, 4, 0};
  for (size_t i = 0; i < pairs.size(); ++i) {
    EXPECT_EQ(index.RowView(i), view[i]) << "row " << i;
    EXPECT_EQ(index.RowLight(i), light[i]) << "row " << i;
    EXPECT_EQ(index.RowPair(i), pair[i]) << "row " << i;
  }
  EXPECT_EQ(index.lights(), 3);
  EXPECT_EQ(index.pairs(), 5);
}

// A fit without a lookup table collects its samples under one view; the
// model and errors must be those of the samples with every view kept.
TEST(LafortuneLargeTable, FitWithoutLookupTableNeedsNoViewsOfItsOwn) {
  const MeasurementTable table = RandomTable(Truth(), 3000, 5);
  LafortuneMipOptions options;
  options.fit.lobes = 1;
  options.fit.lookup_table = false;
  const LafortuneFitResult one = FitLafortuneTable(table, options);
  ASSERT_TRUE(one.report.usable) << one.report.message;
  EXPECT_TRUE(one.params.lut.views.empty());

  std::vector<size_t> rows(table.rows.size());
  for (size_t i = 0; i < rows.size(); ++i) rows[i] = i;
  const ViewIndex index(table);
  const TexelSamples every = CollectSamples(
      table, LafortuneWeighting(table, options.noise), index, rows, nullptr);
  ASSERT_EQ(every.views.size(), table.rows.size());  // a view a row
  const LafortuneFitResult all = FitLafortune(every, options.fit);
  ASSERT_TRUE(all.report.usable) << all.report.message;
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(one.params.params.diffuse[c], all.params.params.diffuse[c]);
    EXPECT_EQ(one.params.params.lobes[0].n[c], all.params.params.lobes[0].n[c]);
    EXPECT_EQ(one.params.params.lobes[0].cz[c],
              all.params.params.lobes[0].cz[c]);
  }
  double rms = 0.0, relative_rms = 0.0;
  LafortuneErrors(all.params, table, index, rows, &rms, &relative_rms);
  EXPECT_EQ(one.report.relative_rms, relative_rms);
}

// Beyond max_one_block_samples the lobes are solved over compressed
// chunks of samples, their terms computed as evaluated. On noisy data
// (the optimum is not the truth, so every row counts) the chunked solve
// must reach the solution of the one block over every sample; on exact
// data of more than the default limit, the model itself.
TEST(LafortuneLargeTable, ChunkedLobeSolveReachesTheOneBlockSolution) {
  MeasurementTable table = RandomTable(Truth(), 6000, 11);
  std::mt19937_64 rng(3);
  std::normal_distribution<double> noise(0.0, 0.02);
  for (TableRow& row : table.rows) row.value *= 1.0 + noise(rng);
  LafortuneMipOptions one_block;
  one_block.fit.lobes = 1;
  one_block.fit.lookup_table = false;
  LafortuneMipOptions chunked = one_block;
  chunked.fit.max_one_block_samples = 1000;  // the first pass too
  const LafortuneFitResult a = FitLafortuneTable(table, one_block);
  const LafortuneFitResult b = FitLafortuneTable(table, chunked);
  ASSERT_TRUE(a.report.usable) << a.report.message;
  ASSERT_TRUE(b.report.usable) << b.report.message;
  EXPECT_GT(a.report.relative_rms, 0.01);  // noisy: not the truth
  EXPECT_NEAR(b.report.relative_rms, a.report.relative_rms,
              1e-9 * a.report.relative_rms);
  const LafortuneParams& p = a.params.params;
  const LafortuneParams& q = b.params.params;
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(q.diffuse[c], p.diffuse[c], 1e-7);
    EXPECT_NEAR(q.lobes[0].n[c], p.lobes[0].n[c], 1e-6 * p.lobes[0].n[c]);
    EXPECT_NEAR(q.lobes[0].cx[c], p.lobes[0].cx[c], 1e-7);
    EXPECT_NEAR(q.lobes[0].cy[c], p.lobes[0].cy[c], 1e-7);
    EXPECT_NEAR(q.lobes[0].cz[c], p.lobes[0].cz[c], 1e-7);
  }

  const LafortuneModel truth = Truth();
  const size_t n = LafortuneFitOptions().max_one_block_samples + 4000;
  const LafortuneFitResult fit =
      FitLafortuneTable(RandomTable(truth, n, 9), one_block);
  ASSERT_TRUE(fit.report.usable) << fit.report.message;
  EXPECT_EQ(fit.report.rows, static_cast<int>(n));
  EXPECT_LT(fit.report.relative_rms, 1e-6);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(fit.params.params.lobes[0].n[c], truth.params.lobes[0].n[c],
                1e-4 * truth.params.lobes[0].n[c]);
    EXPECT_NEAR(fit.params.params.lobes[0].cz[c], truth.params.lobes[0].cz[c],
                1e-6);
  }
}

}  // namespace
}  // namespace clothfit
