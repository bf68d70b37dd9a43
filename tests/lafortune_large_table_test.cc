// Lafortune fits of large tables of random directions (one view a row):
// the per-table index of views, lights and pairs, the fit without a lookup
// table that keeps no per-view arrays, and the lobe solve over compressed
// chunks of samples (fitting/lafortune_lobes.cc) beyond
// LafortuneFitOptions::max_one_block_samples.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <glm/geometric.hpp>
#include <random>
#include <string>
#include <vector>

#include "fitting/lafortune_fit.h"
#include "fitting/lafortune_mip.h"
#include "fitting/lafortune_samples.h"
#include "io/input_error.h"
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

// A table with what the collector merges and skips: rows repeating a
// (light, view) pair with other values, a direction 1e-12 off another (the
// same to 1e-9), views below the surface, zero weights, per-row coverage
// and normals.
MeasurementTable MixedTable() {
  MeasurementTable t = RandomTable(Truth(), 300, 13);
  t.has_alpha = true;
  t.has_normal = true;
  t.has_weight = true;
  const size_t n = t.rows.size();
  for (size_t i = 0; i < n; ++i) {
    TableRow& row = t.rows[i];
    row.alpha = 0.5 + 0.5 * static_cast<double>(i % 7) / 7.0;
    row.normal = glm::normalize(glm::dvec3(0.01 * (i % 5), 0.02, 1.0));
    row.weight = i % 11 == 0 ? 0.0 : 1.0;
    if (i % 13 == 0) row.wo.z = -row.wo.z;  // not reflection
  }
  for (size_t i = 0; i < 60; ++i) {  // repeats, some 1e-12 off
    TableRow row = t.rows[3 * i];
    row.value *= 1.1;
    if (i % 2 == 0) row.wi.x += 1e-12;
    row.source_line = static_cast<int>(t.rows.size()) + 2;
    t.rows.push_back(row);
  }
  return t;
}

void ExpectSameSamples(const TexelSamples& a, const TexelSamples& b) {
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(a.normal, b.normal);
  EXPECT_EQ(a.views, b.views);
  EXPECT_EQ(a.view_alpha, b.view_alpha);
  EXPECT_EQ(a.largest_row_value, b.largest_row_value);
  EXPECT_EQ(a.l, b.l);
  EXPECT_EQ(a.v, b.v);
  EXPECT_EQ(a.value, b.value);
  EXPECT_EQ(a.weight, b.weight);
  EXPECT_EQ(a.view, b.view);
  EXPECT_EQ(a.count_rows, b.count_rows);
  EXPECT_EQ(a.source_line, b.source_line);
}

// Rows added one at a time without an index (views and pairs told apart
// by the collector) give the samples of the table's ViewIndex, bit for bit.
TEST(LafortuneLargeTable, CollectorWithoutAnIndexGivesTheIndexedSamples) {
  const MeasurementTable table = MixedTable();
  std::vector<size_t> rows(table.rows.size());
  for (size_t i = 0; i < rows.size(); ++i) rows[i] = i;
  const ViewIndex index(table);
  ASSERT_LT(index.pairs(), static_cast<int>(table.rows.size()));  // merged
  for (const NoiseKind kind : {NoiseKind::kAbsolute, NoiseKind::kRelative}) {
    NoiseModel noise;
    noise.kind = kind;
    const Weighting weighting = LafortuneWeighting(table, noise);
    for (const bool one_view : {false, true}) {
      SCOPED_TRACE(one_view ? "one view" : "every view");
      int skipped_indexed = 0, skipped = 0;
      const TexelSamples indexed = CollectSamples(table, weighting, index, rows,
                                                  &skipped_indexed, one_view);
      SampleCollector collector(table, one_view);
      for (const TableRow& row : table.rows) collector.Add(row, weighting);
      const TexelSamples samples = collector.Finish(&skipped);
      EXPECT_EQ(skipped, skipped_indexed);
      EXPECT_GT(skipped, 0);
      ExpectSameSamples(samples, indexed);
    }
  }
}

// TableRowPasses over the table's rows.
TableRowPasses PassesOver(const MeasurementTable& table, int* passes) {
  TableRowPasses rows;
  rows.table = &table;
  rows.each = [&table, passes](const std::function<void(const TableRow&)>& f) {
    ++*passes;
    for (const TableRow& row : table.rows) f(row);
  };
  return rows;
}

// The fit of rows passed over (FitLafortuneTable) is the fit of the
// table's indexed samples (FitTexelRows, as every texel of a map): the same
// model and errors, with a lookup table and with candidate lobe counts;
// the passes it takes are those its documentation gives.
TEST(LafortuneLargeTable, FitOfRowsPassedOverIsTheFitOfTheIndexedRows) {
  MeasurementTable table = MixedTable();
  table.has_normal = false;
  for (TableRow& row : table.rows) row.normal = glm::dvec3(0.0, 0.0, 1.0);
  std::vector<size_t> rows(table.rows.size());
  for (size_t i = 0; i < rows.size(); ++i) rows[i] = i;
  const ViewIndex index(table);
  for (const double tolerance : {0.0, 1e-9}) {
    SCOPED_TRACE(tolerance);
    LafortuneMipOptions options;
    options.fit.lobes = 1;
    options.tolerance = tolerance;
    int passes = 0;
    const LafortuneFitResult streamed =
        FitLafortuneRows(PassesOver(table, &passes), options);
    const LafortuneFitResult indexed = FitTexelRows(
        table, LafortuneWeighting(table, options.noise), index, rows, options);
    ASSERT_TRUE(streamed.report.usable) << streamed.report.message;
    // Collecting and the rows' errors; and each of the 4 candidates'
    // errors (none meets 1e-9).
    EXPECT_EQ(passes, tolerance > 0.0 ? 6 : 2);
    EXPECT_EQ(streamed.params.params.lobes.size(),
              indexed.params.params.lobes.size());
    EXPECT_EQ(streamed.params.params.diffuse, indexed.params.params.diffuse);
    for (size_t k = 0; k < indexed.params.params.lobes.size(); ++k) {
      EXPECT_EQ(streamed.params.params.lobes[k].cz,
                indexed.params.params.lobes[k].cz);
      EXPECT_EQ(streamed.params.params.lobes[k].n,
                indexed.params.params.lobes[k].n);
    }
    EXPECT_EQ(streamed.params.lut.color, indexed.params.lut.color);
    EXPECT_EQ(streamed.report.rms, indexed.report.rms);
    EXPECT_EQ(streamed.report.relative_rms, indexed.report.relative_rms);
    EXPECT_EQ(streamed.report.view_relative_rms,
              indexed.report.view_relative_rms);
    EXPECT_EQ(streamed.report.rows_not_used, indexed.report.rows_not_used);
    EXPECT_GT(streamed.report.seconds, 0.0);  // the solves' time, reported
  }
  // Relative noise's default floor takes a pass per channel.
  LafortuneMipOptions relative;
  relative.fit.lobes = 1;
  relative.noise.kind = NoiseKind::kRelative;
  int passes = 0;
  FitLafortuneRows(PassesOver(table, &passes), relative);
  EXPECT_EQ(passes, 5);
}

// A later pass that sees other rows than the first (a file changed while
// it was read) is refused, not fitted or indexed out of range.
TEST(LafortuneLargeTable, RowsThatChangeBetweenPassesAreRefused) {
  MeasurementTable table = RandomTable(Truth(), 500, 17);
  table.source = "t.csv";
  int passes = 0;
  TableRowPasses rows;
  rows.table = &table;
  rows.each = [&](const std::function<void(const TableRow&)>& f) {
    const size_t n = table.rows.size() - (passes++ > 0 ? 1 : 0);
    for (size_t i = 0; i < n; ++i) f(table.rows[i]);
  };
  LafortuneMipOptions options;
  options.fit.lobes = 1;
  try {
    FitLafortuneRows(rows, options);
    ADD_FAILURE() << "no error";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()),
              "t.csv: changed while it was read (500 rows, then 499)");
  }
}

}  // namespace
}  // namespace clothfit
