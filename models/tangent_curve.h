// The tangent curve of a thread in a weave (Sadeghi et al. 2013, Appendix
// A, Table 3; docs/models.md): control-point offsets and segment lengths,
// sampled at equidistant points along the curve.
#pragma once

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "models/math.h"

namespace clothfit {

// A piecewise-linear tangent curve (Appendix A, Table 3): offsets at the
// control points and the length of each segment between them (a zero length
// is a jump), sampled at `samples` equidistant points (m + 0.5) L / T.
struct TangentCurve {
  std::vector<double> offsets_deg;  // K control-point offsets, degrees
  std::vector<double> lengths;      // K - 1 segment lengths, >= 0, sum > 0
  int samples = 0;                  // T >= 1
};

// Samples a curve (docs/models.md). Requires ValidateTangentCurve(c).empty().
inline std::vector<double> SampleTangentCurve(const TangentCurve& c) {
  double total = 0.0;
  for (double l : c.lengths) total += l;
  std::vector<double> out;
  out.reserve(c.samples);
  size_t k = 0;
  double start = 0.0;  // arc length at the start of segment k
  for (int m = 0; m < c.samples; ++m) {
    const double x = (m + 0.5) * total / c.samples;
    // Advance to the segment holding x; zero-length segments are skipped.
    while (k + 1 < c.lengths.size() &&
           (c.lengths[k] == 0.0 || x >= start + c.lengths[k])) {
      start += c.lengths[k];
      ++k;
    }
    const double s =
        c.lengths[k] > 0.0 ? Clamp((x - start) / c.lengths[k], 0.0, 1.0) : 1.0;
    out.push_back(c.offsets_deg[k] +
                  s * (c.offsets_deg[k + 1] - c.offsets_deg[k]));
  }
  return out;
}

inline std::string ValidateTangentCurve(const TangentCurve& c) {
  std::ostringstream msg;
  double total = 0.0;
  for (double l : c.lengths) {
    if (!(std::isfinite(l) && l >= 0.0)) {
      msg << "curve_lengths: must be finite and >= 0, got " << l;
      return msg.str();
    }
    total += l;
  }
  if (c.offsets_deg.size() < 2) {
    msg << "curve_offsets_deg: needs at least 2 control points, got "
        << c.offsets_deg.size();
  } else if (c.lengths.size() + 1 != c.offsets_deg.size()) {
    msg << "curve_lengths: needs " << c.offsets_deg.size() - 1
        << " entries (one per segment), got " << c.lengths.size();
  } else if (!(total > 0.0)) {
    msg << "curve_lengths: total length must be > 0";
  } else if (c.samples < 1 || c.samples > 10000) {
    msg << "samples: must be in [1, 10000], got " << c.samples;
  }
  for (double o : c.offsets_deg) {
    if (msg.str().empty() && !(std::isfinite(o) && std::abs(o) <= 90.0)) {
      msg << "curve_offsets_deg: must be in [-90, 90], got " << o;
    }
  }
  return msg.str();
}

}  // namespace clothfit
