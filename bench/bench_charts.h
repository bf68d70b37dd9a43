// The charts of `clothfit bench` (bench/bench.h) as chart specs
// (charts/chart.h), built from its rows: what WriteBenchReport draws, so
// that the choices (which point is ringed, the y range) can be checked
// without decoding a PNG.
#pragma once

#include <string>
#include <vector>

#include "bench/bench.h"
#include "charts/chart.h"

namespace clothfit {

// Wall time (log) against the held-out error of one model's rows, a
// series per group, the Pareto front; the default configuration
// (BenchRow::is_default) ringed.
ScatterChart SpeedAccuracyChart(const std::string& model,
                                const std::vector<BenchRow>& rows);

// The held-out error against the model size of the rows with a size, a
// line per group sorted by size; ringed: the default configuration's point
// (is_default or default_size), nothing else (the size `--tolerance` picks
// is in the summary's text).
ScatterChart ErrorSizeChart(const std::string& model,
                            const std::vector<BenchRow>& rows);

// Sets the chart's fixed y range to that of its drawable points, widened
// to at least 10 % of their magnitude about its middle (so errors of
// 3e-4 that agree to 1e-9 are neither drawn on a unit range nor spread
// over the whole axis), padded by 8 % and kept >= 0 where all values
// are. A log y axis and a chart without finite points are left alone.
void FitYRangeToData(ScatterChart* chart);

}  // namespace clothfit
