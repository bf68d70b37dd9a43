#include "bench/bench_charts.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

namespace clothfit {
namespace {

// The series of `group`, added when new: joined by lines (a size sweep)
// or points on the Pareto front's set (the speed chart).
ScatterSeries& SeriesOf(ScatterChart* chart, std::map<std::string, size_t>* of,
                        const std::string& group, bool lines) {
  auto [it, added] = of->emplace(group, chart->series.size());
  if (added) {
    chart->series.push_back(ScatterSeries());
    chart->series.back().name = group;
    chart->series.back().lines = lines;
    chart->series.back().pareto = !lines;
  }
  return chart->series[it->second];
}

}  // namespace

ScatterChart SpeedAccuracyChart(const std::string& model,
                                const std::vector<BenchRow>& rows) {
  ScatterChart chart;
  chart.title = model + ": speed against accuracy";
  chart.x_label = "wall time per fit run [s]";
  chart.y_label = "held-out relative RMS error";
  chart.log_x = true;
  chart.pareto = true;
  std::map<std::string, size_t> series_of;
  for (const BenchRow& r : rows) {
    if (r.model != model) continue;
    ChartPoint p;
    p.x = r.wall_median_s;
    p.y = r.value_error;
    p.highlight = r.is_default;
    SeriesOf(&chart, &series_of, r.group, false).points.push_back(p);
  }
  FitYRangeToData(&chart);
  return chart;
}

ScatterChart ErrorSizeChart(const std::string& model,
                            const std::vector<BenchRow>& rows) {
  ScatterChart chart;
  chart.title = model + ": error against model size";
  chart.x_label = model == "cloth"           ? "tangent samples T per thread"
                  : model == "lafortune_mip" ? "texels of the mip level"
                                             : "lobes K";
  chart.log_x = model == "lafortune_mip";
  chart.y_label = "held-out relative RMS error";
  std::vector<BenchRow> sized;
  for (const BenchRow& r : rows) {
    if (r.model == model && std::isfinite(r.size)) sized.push_back(r);
  }
  std::stable_sort(
      sized.begin(), sized.end(),
      [](const BenchRow& a, const BenchRow& b) { return a.size < b.size; });
  std::map<std::string, size_t> series_of;
  for (const BenchRow& r : sized) {
    ChartPoint p;
    p.x = r.size;
    p.y = r.value_error;
    p.highlight = r.is_default || r.default_size;
    p.label = r.label;
    SeriesOf(&chart, &series_of, r.group, true).points.push_back(p);
  }
  FitYRangeToData(&chart);
  return chart;
}

void FitYRangeToData(ScatterChart* chart) {
  if (chart->log_y) return;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const ScatterSeries& s : chart->series) {
    for (const ChartPoint& p : s.points) {
      const bool x_ok = std::isfinite(p.x) && (!chart->log_x || p.x > 0.0);
      if (!x_ok || !std::isfinite(p.y)) continue;
      lo = std::min(lo, p.y);
      hi = std::max(hi, p.y);
    }
  }
  if (!(lo <= hi)) return;
  const bool all_positive = lo >= 0.0;
  // At least 10 % of the values' magnitude: differences far below it (the
  // thread's solvers agree to 1e-5) read as equal, not as a gap.
  const double scale = std::max(std::abs(lo), std::abs(hi));
  const double span = std::max(hi - lo, 0.1 * scale);
  const double mid = 0.5 * (lo + hi);
  lo = mid - 0.5 * span;
  hi = mid + 0.5 * span;
  const double pad = scale > 0.0 ? 0.08 * span : 1.0;
  chart->y_min = all_positive ? std::max(0.0, lo - pad) : lo - pad;
  chart->y_max = hi + pad;
}

}  // namespace clothfit
