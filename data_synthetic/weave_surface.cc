#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <limits>
#include <vector>

#include "data_synthetic/weave_surface_internal.h"
#include "models/math.h"

namespace clothfit {
namespace weave_internal {
namespace {

// Undulation of a thread's centre line, relative to its half-height r_z:
// large enough (> 0.5) that the upper thread covers the lower one over the
// whole crossing.
constexpr double kUndulation = 0.55;

// x - round(x): the signed offset of x from the nearest integer, for
// periodic distances across the tile.
double WrapSigned(double x) { return x - std::round(x); }

// Centre-line height and its derivative d/du at u.
void CentreHeight(const Thread& thread, double u, double* z, double* dz) {
  if (thread.crossings.empty()) {
    const double a = 2.0 * kPi * thread.freq;
    *z = thread.z0 + thread.z1 * std::cos(a * u);
    *dz = -thread.z1 * a * std::sin(a * u);
    return;
  }
  // Crossing i sits at u = (i + 0.5) / m; between two crossings the height
  // follows half a cosine from one crossing's value to the next.
  const int m = static_cast<int>(thread.crossings.size());
  const double t = u * m - 0.5;
  const double cell = std::floor(t);
  const double f = t - cell;
  const int i0 = ((static_cast<int>(cell) % m) + m) % m;
  const double a = thread.crossings[i0];
  const double b = thread.crossings[(i0 + 1) % m];
  *z = a + (b - a) * 0.5 * (1.0 - std::cos(kPi * f));
  *dz = (b - a) * 0.5 * kPi * std::sin(kPi * f) * m;
}

// The thread's surface above (x, y). Outside its footprint (distance > 1)
// the cross-section is clamped to its edge, so that callers can still shade
// points that the bilinear height grid puts just beside a thread.
ThreadSample EvaluateThread(const Thread& thread, double x, double y) {
  const double u = thread.along_x ? x : y;
  const double p = thread.along_x ? y : x;
  const double a = 2.0 * kPi * thread.freq;
  const double offset = thread.bend * std::cos(a * u);
  const double slope = -thread.bend * a * std::sin(a * u);  // dp_c/du
  double zc = 0.0;
  double dzc = 0.0;
  CentreHeight(thread, u, &zc, &dzc);

  // Distance across the centre line, measured perpendicular to it (to
  // first order: the across offset times the cosine of the bend angle).
  const double e = WrapSigned(p - thread.rest - offset);
  const double kappa = 1.0 / std::sqrt(1.0 + slope * slope);
  const double q = std::abs(e) * kappa / thread.half_width;
  const double qc = std::min(q, 1.0);
  const double root = std::sqrt(std::max(0.0, 1.0 - qc * qc));

  ThreadSample sample;
  sample.distance = q;
  sample.height = zc + thread.half_height * root;
  // dz/d(distance) of the half-ellipse, with the slope limited at the
  // thread's edge (where the true cross-section is vertical).
  const double dz_dd =
      -thread.half_height * qc / (thread.half_width * std::max(root, 0.05));
  const double dz_dp = dz_dd * (e >= 0.0 ? 1.0 : -1.0) * kappa;
  const double dz_du = dzc - dz_dp * slope;
  if (thread.along_x) {
    sample.gradient = glm::dvec2(dz_du, dz_dp);
    sample.tangent = glm::normalize(glm::dvec3(1.0, slope, dzc));
  } else {
    sample.gradient = glm::dvec2(dz_dp, dz_du);
    sample.tangent = glm::normalize(glm::dvec3(slope, 1.0, dzc));
  }
  return sample;
}

// A thread colour: the base colour with a small per-thread variation.
glm::dvec3 VaryColour(const glm::dvec3& base, Random* random) {
  const double brightness = 1.0 + 0.12 * (2.0 * random->Uniform() - 1.0);
  glm::dvec3 colour;
  for (int c = 0; c < 3; ++c) {
    colour[c] =
        base[c] * brightness * (1.0 + 0.05 * (2.0 * random->Uniform() - 1.0));
  }
  return colour;
}

const glm::dvec3 kWarpColour(0.70, 0.22, 0.16);  // reddish
const glm::dvec3 kWeftColour(0.16, 0.30, 0.72);  // bluish

}  // namespace

// The threads of one tile of the pattern.
std::vector<Thread> BuildThreads(const VirtualGonioOptions& options,
                                 Random* random) {
  std::vector<Thread> threads;
  auto woven = [&](int m, auto warp_over) {
    // m warps at y = (j + 0.5) / m, m wefts at x = (i + 0.5) / m; at the
    // crossing (i, j) the upper thread's centre is at +A, the lower's at -A.
    const double scale = (1.0 / m) / kReferencePitch;
    const double rz = options.thread_radius * scale;
    const double w = 0.5 * (1.0 / m - options.gap * scale);
    const double amplitude = kUndulation * rz;
    for (int j = 0; j < m; ++j) {
      Thread warp;
      warp.along_x = true;
      warp.rest = (j + 0.5) / m;
      warp.half_width = w;
      warp.half_height = rz;
      for (int i = 0; i < m; ++i) {
        warp.crossings.push_back(warp_over(i, j) ? amplitude : -amplitude);
      }
      warp.colour = VaryColour(kWarpColour, random);
      threads.push_back(warp);
    }
    for (int i = 0; i < m; ++i) {
      Thread weft;
      weft.along_x = false;
      weft.rest = (i + 0.5) / m;
      weft.half_width = w;
      weft.half_height = rz;
      for (int j = 0; j < m; ++j) {
        weft.crossings.push_back(warp_over(i, j) ? -amplitude : amplitude);
      }
      weft.colour = VaryColour(kWeftColour, random);
      threads.push_back(weft);
    }
  };

  switch (options.pattern) {
    case WeavePattern::kPlain:
      woven(2, [](int i, int j) { return (i + j) % 2 == 0; });
      break;
    case WeavePattern::kSatin:
      // 5-harness satin, move 2: warp j passes under weft 2j mod 5 only.
      woven(5, [](int i, int j) { return i != (2 * j) % 5; });
      break;
    case WeavePattern::kKnit: {
      // Loop legs: 4 threads along y (2 wales of 2 legs, pitch 0.25). The
      // legs of a wale bend towards each other at the course lines
      // (y = 0, 0.5), where they dive under the course thread, and apart
      // between them, where they rise: V-shaped loops, 2 courses per tile.
      const double pitch = 0.25;
      const double scale = pitch / kReferencePitch;
      const double rz = options.thread_radius * scale;
      const double w = 0.5 * (pitch - options.gap * scale);
      const double amplitude = kUndulation * rz;
      for (int wale = 0; wale < 2; ++wale) {
        const double centre = (wale + 0.5) / 2.0;
        for (int side = -1; side <= 1; side += 2) {
          Thread leg;
          leg.along_x = false;
          leg.rest = centre + side * 0.5 * pitch;
          leg.bend = -side * 0.16 * pitch;  // towards the wale centre at y = 0
          leg.freq = 2.0;
          leg.z0 = 0.3 * amplitude;
          leg.z1 = -0.7 * amplitude;  // low at the course lines
          leg.half_width = w;
          leg.half_height = rz;
          leg.colour = VaryColour(kWeftColour, random);
          threads.push_back(leg);
        }
      }
      // Course threads (the loop heads) along x at y = 0 and 0.5, straight
      // and level, above the legs where these dive (-0.4 A).
      for (int course = 0; course < 2; ++course) {
        Thread head;
        head.along_x = true;
        head.rest = course * 0.5;
        head.z0 = 0.2 * amplitude;
        head.half_width = w;
        head.half_height = rz;
        head.colour = VaryColour(kWarpColour, random);
        threads.push_back(head);
      }
      break;
    }
  }
  return threads;
}

SurfacePoint EvaluateSurface(const std::vector<Thread>& threads, double x,
                             double y) {
  SurfacePoint best;
  double nearest = std::numeric_limits<double>::infinity();
  for (size_t k = 0; k < threads.size(); ++k) {
    const ThreadSample sample = EvaluateThread(threads[k], x, y);
    const bool covered = sample.distance <= 1.0;
    if (covered) {
      if (!best.covered || sample.height > best.sample.height) {
        best.covered = true;
        best.thread = static_cast<int>(k);
        best.sample = sample;
      }
    } else if (!best.covered && sample.distance < nearest) {
      nearest = sample.distance;
      best.thread = static_cast<int>(k);
      best.sample = sample;
    }
  }
  return best;
}

HeightGrid::HeightGrid(const std::vector<Thread>& threads, int n)
    : n_(n), z_(n * n) {
  double lowest = std::numeric_limits<double>::infinity();
  double highest = -std::numeric_limits<double>::infinity();
  double thickest = 0.0;
  for (const Thread& thread : threads) {
    thickest = std::max(thickest, thread.half_height);
  }
  std::vector<char> hole(z_.size());
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const SurfacePoint point = EvaluateSurface(
          threads, static_cast<double>(i) / n, static_cast<double>(j) / n);
      const size_t k = static_cast<size_t>(j) * n + i;
      hole[k] = !point.covered;
      z_[k] = point.sample.height;
      if (point.covered) {
        lowest = std::min(lowest, z_[k]);
        highest = std::max(highest, z_[k]);
      }
    }
  }
  if (!std::isfinite(lowest)) lowest = highest = 0.0;  // all holes
  floor_ = lowest - 0.1 * thickest;
  top_ = highest + 1e-9;
  for (size_t k = 0; k < z_.size(); ++k) {
    if (hole[k]) z_[k] = floor_ - thickest;
  }
}

double HeightGrid::Height(double x, double y) const {
  const double fx = (x - std::floor(x)) * n_;
  const double fy = (y - std::floor(y)) * n_;
  int i0 = static_cast<int>(fx);
  int j0 = static_cast<int>(fy);
  if (i0 >= n_) i0 = n_ - 1;  // x just below 1 rounding up
  if (j0 >= n_) j0 = n_ - 1;
  const double ax = fx - i0;
  const double ay = fy - j0;
  const int i1 = i0 + 1 == n_ ? 0 : i0 + 1;
  const int j1 = j0 + 1 == n_ ? 0 : j0 + 1;
  const double* row0 = &z_[static_cast<size_t>(j0) * n_];
  const double* row1 = &z_[static_cast<size_t>(j1) * n_];
  const double bottom = row0[i0] + ax * (row0[i1] - row0[i0]);
  const double upper = row1[i0] + ax * (row1[i1] - row1[i0]);
  return bottom + ay * (upper - bottom);
}

// Marches the view ray origin + tau * dir (dir.z < 0) down until it meets
// the surface (true, *hit = the refined intersection) or drops below the
// floor through a hole (false).
bool MarchView(const HeightGrid& grid, const glm::dvec3& origin,
               const glm::dvec3& dir, double step, glm::dvec3* hit) {
  double above = 0.0;
  for (int k = 1;; ++k) {
    const double tau = k * step;
    const glm::dvec3 p = origin + tau * dir;
    if (p.z <= grid.Height(p.x, p.y)) {
      double below = tau;
      for (int b = 0; b < kBisections; ++b) {
        const double mid = 0.5 * (above + below);
        const glm::dvec3 q = origin + mid * dir;
        if (q.z <= grid.Height(q.x, q.y)) {
          below = mid;
        } else {
          above = mid;
        }
      }
      *hit = origin + below * dir;
      return true;
    }
    if (p.z < grid.floor()) return false;
    above = tau;
  }
}

// True when the ray from `from` towards `dir` (dir.z > 0) meets the surface
// before it rises above the tallest thread. The ray starts a small distance
// off the surface (it begins exactly on the bilinear surface).
bool Shadowed(const HeightGrid& grid, const glm::dvec3& from,
              const glm::dvec3& dir, double step) {
  constexpr double kBias = 1e-5;
  for (double tau = 0.25 * step;; tau += step) {
    const glm::dvec3 p = from + tau * dir;
    if (p.z > grid.top()) return false;
    if (p.z < grid.Height(p.x, p.y) - kBias) return true;
  }
}

}  // namespace weave_internal
}  // namespace clothfit
