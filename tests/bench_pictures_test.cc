// What the bench's pictures show (bench/bench_charts.h, the slab error map,
// the holes' angle chart) and the memory the bench reports: the default
// ringed once, y ranges from the data, cells and colour bar in one unit,
// the extension visible beside the ground truth, the memory a fit adds.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <vector>

#include "bench/bench_charts.h"
#include "bench/bench_internal.h"
#include "bench/hole_charts.h"
#include "bench/slab_error_chart.h"
#include "tests/io_test_util.h"

namespace clothfit {
namespace {

namespace fs = std::filesystem;

BenchRow Row(const std::string& model, const std::string& group, double time,
             double error, double size = std::nan(""),
             bool is_default = false) {
  BenchRow r;
  r.model = model;
  r.group = group;
  r.wall_median_s = time;
  r.value_error = error;
  r.size = size;
  r.is_default = is_default;
  return r;
}

// The ringed points of a chart as (series name, x).
std::vector<std::pair<std::string, double>> Ringed(const ScatterChart& c) {
  std::vector<std::pair<std::string, double>> ringed;
  for (const ScatterSeries& s : c.series) {
    for (const ChartPoint& p : s.points) {
      if (p.highlight) ringed.emplace_back(s.name, p.x);
    }
  }
  return ringed;
}

TEST(BenchCharts, SpeedChartRingsTheDefaultOnceAndTakesYFromTheErrors) {
  // The thread bench's linear solvers: the same error to 1e-9.
  const std::vector<BenchRow> rows = {
      Row("thread", "starts=1", 0.02, 3e-4, std::nan(""), true),
      Row("thread", "linear solver", 0.03, 3e-4),
      Row("thread", "linear solver", 0.05, 3e-4 + 1e-13),
      Row("cloth", "starts=1", 0.5, 0.2, std::nan(""), true)};
  const ScatterChart c = SpeedAccuracyChart("thread", rows);
  EXPECT_EQ(Ringed(c),
            (std::vector<std::pair<std::string, double>>{{"starts=1", 0.02}}));
  EXPECT_LT(c.y_min, 3e-4);
  EXPECT_GT(c.y_max, 3e-4);
  EXPECT_GE(c.y_min, 0.0);
  EXPECT_LT(c.y_max, 1e-3);  // not a unit range around 3e-4
  // ... nor a difference of 1e-13 spread over the axis.
  EXPECT_GT(c.y_max - c.y_min, 0.1 * 3e-4);
}

TEST(BenchCharts, SizeChartRingsTheDefaultConfigurationOnly) {
  // Lafortune: lut=off reaches its best error at K = 0 and lut=on at
  // K = 1, so the size --tolerance picks differs from the default K = 2.
  const std::vector<BenchRow> lafortune = {
      Row("lafortune", "lut=off", 1, 0.10, 0),
      Row("lafortune", "lut=off", 2, 0.10, 2),
      Row("lafortune", "lut=on", 1, 0.05, 1),
      Row("lafortune", "lut=on", 2, 0.05, 2, true)};
  EXPECT_EQ(Ringed(ErrorSizeChart("lafortune", lafortune)),
            (std::vector<std::pair<std::string, double>>{{"lut=on", 2.0}}));
  // Mip levels: level 1 (1 texel) is better, level 0 (4 texels) the default.
  const std::vector<BenchRow> mip = {
      Row("lafortune_mip", "lobes=2 lut=on", 1, 0.3, 4, true),
      Row("lafortune_mip", "lobes=2 lut=on", 1, 0.1, 1)};
  EXPECT_EQ(
      Ringed(ErrorSizeChart("lafortune_mip", mip)),
      (std::vector<std::pair<std::string, double>>{{"lobes=2 lut=on", 4.0}}));
  // Cloth: the default configuration repeated in the size sweep.
  std::vector<BenchRow> cloth = {
      Row("cloth", "start search on", 1, 0.1, std::nan(""), true),
      Row("cloth", "tangent samples", 1, 0.2, 1),
      Row("cloth", "tangent samples", 1, 0.1, 8)};
  cloth[2].default_size = true;
  const ScatterChart c = ErrorSizeChart("cloth", cloth);
  EXPECT_EQ(
      Ringed(c),
      (std::vector<std::pair<std::string, double>>{{"tangent samples", 8.0}}));
  EXPECT_LE(c.y_min, 0.1);
  EXPECT_GE(c.y_max, 0.2);
  EXPECT_LT(c.y_max, 0.3);
}

// The memory a run adds at its peak, not the process's: 64 MB touched
// reads as about 64 MB (below 96: AddressSanitizer's shadow adds 1/8),
// and a run after it that allocates nothing as about nothing. One repeat:
// AddressSanitizer keeps freed blocks in quarantine, so a second would
// add its 64 MB again.
TEST(BenchMemory, PeakIsWhatTheRunAddsNotWhatTheProcessHolds) {
  BenchOptions o;
  o.repeats = 1;
  const BenchRow big = bench_internal::Measure(o, []() {
    std::vector<char> block(64 << 20);
    std::memset(block.data(), 1, block.size());
    volatile char sink = block[12345];
    (void)sink;
    return bench_internal::Outcome();
  });
  if (std::isnan(big.peak_mb)) GTEST_SKIP() << "no VmHWM reset here";
  EXPECT_GT(big.peak_mb, 60.0);
  EXPECT_LT(big.peak_mb, 96.0);
  const BenchRow none =
      bench_internal::Measure(o, []() { return bench_internal::Outcome(); });
  EXPECT_GE(none.peak_mb, 0.0);
  EXPECT_LT(none.peak_mb, 4.0);
}

TEST(SlabErrorChart, CellsColourBarAndThresholdShareTheUnitPercent) {
  SlabErrorMap map;
  map.options.taus = {0.01, 0.1};
  map.options.albedos = {0.5};
  map.cells.resize(2);
  map.cells[0].relative_rms_error = 0.005;  // 0.5 %: inside the regime
  map.cells[1].relative_rms_error = 0.02;   // 2 %: outside
  const HeatMap h = SlabErrorHeatMap(map);
  ASSERT_EQ(h.panels.size(), 1u);
  EXPECT_EQ(h.unit, "%");
  EXPECT_EQ(h.panels[0].values, (std::vector<double>{0.5, 2.0}));
  EXPECT_EQ(h.panels[0].cell_text, (std::vector<std::string>{"0.5%", "2%"}));
  EXPECT_LT(h.panels[0].values[0], h.threshold);  // not outlined
  EXPECT_GT(h.panels[0].values[1], h.threshold);  // outlined
  EXPECT_LE(h.lo, 0.5);
  EXPECT_GE(h.hi, 2.0);
}

// Where the extension equals the truth its curve is still seen: pixels of
// its colour in the plot (left of the legend).
TEST(HoleCharts, ExtensionCurveIsVisibleWhereItMatchesTheTruth) {
  const fs::path dir = testing_util::FreshTestDir("bench_pictures_test_");
  AngleCurve curve;
  for (int i = 0; i <= 8; ++i) {
    curve.theta_deg.push_back(10.0 * i);
    curve.truth.push_back(0.6 - 0.06 * i);
    curve.alg31.push_back(0.6 - 0.07 * i);
  }
  curve.extension = curve.truth;
  const std::string png = (dir / "angle.png").string();
  WriteAngleChart(curve, "test", png, (dir / "angle.csv").string());
  auto in = OIIO::ImageInput::open(png);
  ASSERT_TRUE(in);
  const int w = in->spec().width, h = in->spec().height;
  std::vector<unsigned char> rgb(size_t(w) * h * 3);
  ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, rgb.data()));
  int blue = 0;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w * 7 / 10; ++x) {
      const unsigned char* p = &rgb[(size_t(y) * w + x) * 3];
      blue += std::abs(p[0] - 31) < 20 && std::abs(p[1] - 119) < 20 &&
              std::abs(p[2] - 180) < 20;
    }
  }
  EXPECT_GT(blue, 200);
}

}  // namespace
}  // namespace clothfit
