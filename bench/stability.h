// clothfit bench --stability: how often each fitter succeeds as
// the data get worse - noise level, distance of the initial guess from the
// truth, angular coverage of the data, fraction of gross outliers - over
// several random seeds per level. docs/bench.md names each failure mode and
// what to do about it.
//
// Success: the fit reports usable and converged (exit status 0) and its
// model is within kStabilitySuccessError (relative RMS) of the truth at
// held-out directions. Data: synthetic, from the satin's warp thread
// (thread fitter), the whole satin (cloth fitter, from the generic start)
// and a thin slab (tau 0.05), brdf tables with multiplicative Gaussian
// noise (2 % unless the noise is the knob); the holes fit (thickness, and
// with "holes+wall" the wall colour) on ray-traced transmittance of random
// masks (stability.cc HolesRun).
#pragma once

#include <string>
#include <vector>

#include "bench/bench.h"

namespace clothfit {

constexpr double kStabilitySuccessError = 0.05;

struct StabilityRow {
  std::string fitter;  // "thread", "cloth", "slab", "thread+cauchy", "holes",
                       // "holes+cauchy", "holes+wall"
  std::string knob;    // "noise", "start_distance", "coverage", "outliers"
  double level = 0.0;  // the knob's value (coverage: the largest polar angle
                       // in degrees; negative: grazing only, theta >= -level)
  std::string level_label;
  int runs = 0, successes = 0;
  double median_error = 0.0;  // held-out relative RMS, median over seeds
};

std::vector<StabilityRow> RunStability(const BenchOptions& options);

// DIR/stability.csv, DIR/stability_<knob>.png (success rate against the
// level, a line per fitter) and DIR/stability.md; returns the files.
std::vector<std::string> WriteStabilityReport(
    const std::vector<StabilityRow>& rows, const std::string& dir);

}  // namespace clothfit
