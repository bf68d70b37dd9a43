// Charts and the bench's bookkeeping (charts/): the Pareto front, the
// tolerance choice, and PNG files that decode.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "bench/bench.h"
#include "charts/chart.h"
#include "charts/heat_map.h"
#include "io/atomic_file.h"
#include "io/input_error.h"
#include "tests/io_test_util.h"

namespace clothfit {
namespace {

namespace fs = std::filesystem;

ChartPoint P(double x, double y) {
  ChartPoint p;
  p.x = x;
  p.y = y;
  return p;
}

ScatterChart TwoSeries() {
  ScatterChart spec;
  spec.pareto = true;
  ScatterSeries a, b;
  a.pareto = b.pareto = true;
  // (time, error): (1, 5) (2, 3) (4, 4) | (3, 1) (5, 2) (0.5, 9)
  a.points = {P(1, 5), P(2, 3), P(4, 4)};
  b.points = {P(3, 1), P(5, 2), P(0.5, 9)};
  spec.series = {a, b};
  return spec;
}

TEST(ChartTest, ParetoFrontKeepsOnlyUndominatedPointsByTime) {
  const std::vector<std::pair<int, int>> front = ParetoFront(TwoSeries());
  const std::vector<std::pair<int, int>> expected = {
      {1, 2}, {0, 0}, {0, 1}, {1, 0}};  // x = 0.5, 1, 2, 3
  EXPECT_EQ(front, expected);
}

TEST(ChartTest, ToleranceChoiceIsTheSmallestSizeNearTheBest) {
  std::vector<BenchRow> rows(4);
  const double errors[] = {0.9, 0.5, 0.41, 0.40};
  for (int k = 0; k < 4; ++k) {
    rows[k].size = k;
    rows[k].value_error = errors[k];
  }
  EXPECT_EQ(ToleranceChoice(rows, 0.05), 2.0);  // 0.41 <= 0.40 * 1.05
  EXPECT_EQ(ToleranceChoice(rows, 0.0), 3.0);
  EXPECT_EQ(ToleranceChoice(rows, 0.3), 1.0);  // 0.5 <= 0.52 < 0.9
  rows.clear();
  EXPECT_TRUE(std::isnan(ToleranceChoice(rows, 0.1)));
}

bool IsPng(const std::string& path) {
  const std::string bytes = ReadFileToString(path);
  return bytes.size() > 1000 && bytes.compare(1, 3, "PNG") == 0;
}

TEST(ChartTest, ChartsAreWrittenWithAndWithoutDrawablePoints) {
  const fs::path dir = testing_util::FreshTestDir("charts_test_");
  ScatterChart spec = TwoSeries();
  spec.log_x = true;
  spec.series[0].points.push_back(P(-1.0, 2.0));  // not on a log axis
  spec.series[0].points.push_back(P(NAN, 2.0));
  const std::string path = (dir / "c.png").string();
  WriteScatterChartPng(spec, path);
  EXPECT_TRUE(IsPng(path));
  ScatterChart empty;
  WriteScatterChartPng(empty, (dir / "e.png").string());
  EXPECT_TRUE(IsPng((dir / "e.png").string()));
  PolarPanel panel;
  panel.model_angle_deg = {-10, 0, 10};
  panel.model_value = {1, 2, 1};
  panel.measured_angle_deg = {5};
  panel.measured_value = {1.5};
  WritePolarPlotPng({panel, panel}, "t", (dir / "p.png").string());
  EXPECT_TRUE(IsPng((dir / "p.png").string()));
  EXPECT_THROW(WriteScatterChartPng(spec, (dir / "missing" / "c.png").string()),
               std::exception);
}

// A log axis over a small range was labelled only where linear ticks fell
// (0.02 ... 0.06 for data spanning 0.02 to 0.06, nothing for 0.01 to 0.5
// but its ends): the decades and their 2 and 5 now, every mantissa inside
// a decade, decades alone over many.
TEST(ChartTest, LogAxesLabelDecadesAndTwoFiveTicks) {
  auto near = [](const std::vector<double>& got,
                 const std::vector<double>& want) {
    if (got.size() != want.size()) return false;
    for (size_t i = 0; i < got.size(); ++i) {
      if (std::abs(got[i] - want[i]) > 1e-9 * want[i]) return false;
    }
    return true;
  };
  const std::vector<double> wide = AxisTicks(2e-5, 3.0, true);
  EXPECT_TRUE(near(wide, {1e-4, 1e-3, 1e-2, 1e-1, 1})) << wide.size();
  const std::vector<double> two = AxisTicks(0.008, 0.6, true);
  EXPECT_TRUE(near(two, {0.01, 0.02, 0.05, 0.1, 0.2, 0.5})) << two.size();
  const std::vector<double> one = AxisTicks(0.018, 0.065, true);
  EXPECT_TRUE(near(one, {0.02, 0.03, 0.04, 0.05, 0.06})) << one.size();
  const std::vector<double> linear = AxisTicks(0.0, 0.95, false);
  EXPECT_TRUE(near(linear, {0.0, 0.2, 0.4, 0.6, 0.8})) << linear.size();
  // Twenty decades: at most a dozen labels, still decades.
  const std::vector<double> many = AxisTicks(1e-12, 1e8, true);
  EXPECT_LE(many.size(), 12u);
  EXPECT_GE(many.size(), 5u);
  for (double t : many) {
    EXPECT_NEAR(std::log10(t), std::round(std::log10(t)), 1e-9);
  }
}

// The PNG's width from its IHDR chunk (bytes 16-19, big-endian).
int PngWidth(const std::string& path) {
  const std::string bytes = ReadFileToString(path);
  int width = 0;
  for (int i = 16; i < 20; ++i) {
    width = width * 256 + static_cast<unsigned char>(bytes.at(i));
  }
  return width;
}

// The one heat map (charts/heat_map.h): panels side by side over one
// colour scale (from the values when no range is given; non-finite cells
// and the default value text allowed); inconsistent layouts are refused.
TEST(ChartTest, HeatMapsDrawPanelsSideBySideAndRefuseBadLayouts) {
  const fs::path dir = testing_util::FreshTestDir("charts_test_");
  HeatMap map;
  map.title = "t";
  map.x_labels = {"1", "2", "3"};
  map.y_labels = {"top", "bottom"};
  map.panels = {{"a", {0.1, 0.2, NAN, 0.4, 0.5, 0.6}, {}}};
  const std::string one = (dir / "one.png").string();
  WriteHeatMapPng(map, one);
  EXPECT_TRUE(IsPng(one));
  map.panels.push_back({"b", {1, 2, 3, 4, 5, 6}, {"", "", "", "", "", "x"}});
  const std::string two = (dir / "two.png").string();
  WriteHeatMapPng(map, two);
  EXPECT_TRUE(IsPng(two));
  EXPECT_GE(PngWidth(two) - PngWidth(one), 3 * 60);  // a panel of 3 columns
  map.log_scale = true;  // range from the positive values
  WriteHeatMapPng(map, two);
  map.lo = -1.0;
  map.hi = 1.0;
  EXPECT_THROW(WriteHeatMapPng(map, two), InputError);  // log of lo <= 0
  map.log_scale = false;
  map.panels[1].values.pop_back();
  EXPECT_THROW(WriteHeatMapPng(map, two), InputError);
  map.panels.clear();
  EXPECT_THROW(WriteHeatMapPng(map, two), InputError);
}

}  // namespace
}  // namespace clothfit
