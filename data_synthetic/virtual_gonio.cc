// Virtual gonioreflectometer: see virtual_gonio.h for the geometry, the
// sampling and the shading. Structure of the computation:
//
//  1. The pattern becomes a list of threads (Thread), each a centre line
//     over the tile with a half-elliptic cross-section. Evaluating a thread
//     at (x, y) gives its surface height there, the gradient of that height
//     (for the normal) and its tangent (for the glossy term).
//  2. The surface (the highest thread, or a hole) is sampled once on a
//     grid x grid lattice (HeightGrid); all ray marching runs against the
//     bilinear interpolation of that lattice, so view and shadow rays see
//     the same surface.
//  3. Per texel (in parallel, one texel per task), per view: the k x k view
//     rays are marched down from the top of the bounding box; each hit
//     stores its position and, from the exact thread geometry, its normal,
//     tangent and colour. These do not depend on the light and serve all
//     n^2 lights; each (hit, light) then casts one shadow ray.
#include "data_synthetic/virtual_gonio.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <limits>
#include <sstream>
#include <thread>
#include <vector>

#include "data_synthetic/synthetic_table.h"
#include "io/input_error.h"
#include "models/math.h"

namespace clothfit {
namespace {

// Directions stay within 85 degrees of the normal (the lowest stratum
// starts there).
const double kMinCosTheta = std::cos(85.0 * kPi / 180.0);
// Undulation of a thread's centre line, relative to its half-height r_z:
// large enough (> 0.5) that the upper thread covers the lower one over the
// whole crossing.
constexpr double kUndulation = 0.55;
// Exponent of the glossy (Kajiya-Kay-like) lobe.
constexpr double kGlossyExponent = 32.0;
// March step, relative to the smaller of the thread's half-width and
// half-height; intersections are then refined by bisection.
constexpr double kStepFraction = 0.08;
constexpr int kBisections = 14;

// The thread pitch the options' thread_radius and gap refer to.
constexpr double kReferencePitch = 0.5;

// x - round(x): the signed offset of x from the nearest integer, for
// periodic distances across the tile.
double WrapSigned(double x) { return x - std::round(x); }

// One thread over the tile. `along_x` threads (warp) run along x at rest
// position y = rest (and vice versa for weft). The along-coordinate u is x
// for warp, y for weft; the across-coordinate p the other one.
//   centre line across:  p_c(u) = rest + bend * cos(2 pi freq u)
//   centre line height:  crossings.empty() ? z0 + z1 cos(2 pi freq u)
//                        : cosine interpolation of crossings[i] placed at
//                          u_i = (i + 0.5) / crossings.size()
struct Thread {
  bool along_x = true;
  double rest = 0.0;
  double bend = 0.0;
  double freq = 0.0;
  double z0 = 0.0;
  double z1 = 0.0;
  std::vector<double> crossings;
  double half_width = 0.1;   // w
  double half_height = 0.1;  // r_z
  glm::dvec3 colour{0.5};
};

struct ThreadSample {
  double height = 0.0;       // surface height of the thread at (x, y)
  double distance = 0.0;     // distance from the centre line / half-width
  glm::dvec2 gradient{0.0};  // (dz/dx, dz/dy) of that surface
  glm::dvec3 tangent{1.0, 0.0, 0.0};
};

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

// The surface point above (x, y): the highest thread whose footprint
// contains it. `covered` is false in a hole; `thread` is then the nearest
// thread (smallest relative distance), evaluated at its clamped edge.
struct SurfacePoint {
  bool covered = false;
  int thread = 0;
  ThreadSample sample;
};

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

// The surface sampled at grid x grid lattice points (i / grid, j / grid),
// periodic, with bilinear lookup. Holes are stored below `floor`, the level
// under which a descending ray can no longer meet anything.
class HeightGrid {
 public:
  HeightGrid(const std::vector<Thread>& threads, int n) : n_(n), z_(n * n) {
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

  double Height(double x, double y) const {
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

  double floor() const { return floor_; }
  double top() const { return top_; }

 private:
  int n_;
  std::vector<double> z_;
  double floor_ = 0.0;
  double top_ = 0.0;
};

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

// What a view ray found: the shading frame at its hit.
struct ViewHit {
  bool hit = false;
  glm::dvec3 position{0.0};
  glm::dvec3 normal{0.0, 0.0, 1.0};
  glm::dvec3 tangent{1.0, 0.0, 0.0};
  glm::dvec3 colour{0.0};
};

std::vector<glm::dvec3> HemisphereDirections(int n) {
  std::vector<glm::dvec3> directions;
  directions.reserve(static_cast<size_t>(n) * n);
  for (int i = 0; i < n; ++i) {
    const double cos_theta =
        kMinCosTheta + (1.0 - kMinCosTheta) * (i + 0.5) / n;
    const double sin_theta = std::sqrt(1.0 - cos_theta * cos_theta);
    for (int j = 0; j < n; ++j) {
      const double phi = 2.0 * kPi * (j + 0.5) / n;
      directions.emplace_back(sin_theta * std::cos(phi),
                              sin_theta * std::sin(phi), cos_theta);
    }
  }
  return directions;
}

void Validate(const VirtualGonioOptions& o) {
  auto fail = [](const std::string& what) {
    throw InputError("virtual gonioreflectometer: " + what);
  };
  if (o.texels < 1) fail("texels must be >= 1");
  if (o.directions < 1) fail("directions must be >= 1");
  if (o.supersample < 1) fail("supersample must be >= 1");
  if (o.grid < 16) fail("grid must be >= 16");
  if (o.threads < 0) fail("threads must be >= 0");
  if (!(o.thread_radius > 0.0) || !std::isfinite(o.thread_radius)) {
    fail("thread_radius must be > 0");
  }
  if (!(o.gap >= 0.0 && o.gap < kReferencePitch)) {
    fail("gap must be in [0, 0.5)");
  }
  if (!(o.glossy >= 0.0) || !std::isfinite(o.glossy)) {
    fail("glossy must be >= 0");
  }
}

std::string FormatNumber(double x) {
  std::ostringstream out;
  out << x;
  return out.str();
}

}  // namespace

const char* WeavePatternName(WeavePattern pattern) {
  switch (pattern) {
    case WeavePattern::kPlain:
      return "plain";
    case WeavePattern::kSatin:
      return "satin";
    case WeavePattern::kKnit:
      return "knit";
  }
  return "plain";
}

bool ParseWeavePattern(const std::string& name, WeavePattern* pattern) {
  for (WeavePattern p :
       {WeavePattern::kPlain, WeavePattern::kSatin, WeavePattern::kKnit}) {
    if (name == WeavePatternName(p)) {
      *pattern = p;
      return true;
    }
  }
  return false;
}

MeasurementTable MeasureVirtualGonio(const VirtualGonioOptions& options) {
  Validate(options);
  const int s_count = options.texels;
  const int n = options.directions;
  const int k = options.supersample;
  const int texel_count = s_count * s_count;
  const int subsamples = k * k;

  // Everything random is drawn here, serially: thread colours, then the
  // jitter of every texel's sample points (fixed for all views).
  Random random(options.seed);
  const std::vector<Thread> threads = BuildThreads(options, &random);
  std::vector<glm::dvec2> points(static_cast<size_t>(texel_count) * subsamples);
  for (int t = 0; t < s_count; ++t) {
    for (int s = 0; s < s_count; ++s) {
      for (int b = 0; b < k; ++b) {
        for (int a = 0; a < k; ++a) {
          const double x = (s + (a + random.Uniform()) / k) / s_count;
          const double y = (t + (b + random.Uniform()) / k) / s_count;
          points[(static_cast<size_t>(t) * s_count + s) * subsamples + b * k +
                 a] = glm::dvec2(x, y);
        }
      }
    }
  }

  const HeightGrid grid(threads, options.grid);
  double finest = std::numeric_limits<double>::infinity();
  for (const Thread& thread : threads) {
    finest = std::min({finest, thread.half_width, thread.half_height});
  }
  // Never below a quarter grid cell (nothing finer exists in the grid);
  // with gap close to the pitch threads can become very thin.
  const double step = std::max(kStepFraction * finest, 0.25 / options.grid);
  const std::vector<glm::dvec3> dirs = HemisphereDirections(n);
  const int pairs = n * n;
  const double gloss_norm =
      options.glossy * (kGlossyExponent + 2.0) / (2.0 * kPi);

  MeasurementTable table;
  table.quantity = Quantity::kCosineWeighted;
  table.channels = 3;
  table.direction_columns = DirectionColumns::kVectors;
  table.has_texels = true;
  table.has_alpha = true;
  table.has_normal = true;
  table.rows.resize(static_cast<size_t>(texel_count) * pairs * pairs);

  // One texel: all its views, lights and sub-samples. Writes only that
  // texel's rows, so the result does not depend on the scheduling.
  auto measure_texel = [&](int texel) {
    const int s = texel % s_count;
    const int t = texel / s_count;
    std::vector<ViewHit> hits(subsamples);
    glm::dvec3 normal_sum(0.0);
    for (int view = 0; view < pairs; ++view) {
      const glm::dvec3& v = dirs[view];
      int covered = 0;
      for (int sub = 0; sub < subsamples; ++sub) {
        ViewHit& h = hits[sub];
        const glm::dvec2& xy =
            points[static_cast<size_t>(texel) * subsamples + sub];
        h = ViewHit();
        glm::dvec3 position;
        if (!MarchView(grid, glm::dvec3(xy, grid.top()), -v, step, &position)) {
          continue;
        }
        const SurfacePoint point =
            EvaluateSurface(threads, position.x, position.y);
        h.hit = true;
        h.position = position;
        h.normal = glm::normalize(glm::dvec3(-point.sample.gradient, 1.0));
        h.tangent = point.sample.tangent;
        h.colour = threads[point.thread].colour;
        normal_sum += h.normal;
        ++covered;
      }
      const double alpha = static_cast<double>(covered) / subsamples;
      for (int light = 0; light < pairs; ++light) {
        const glm::dvec3& l = dirs[light];
        const glm::dvec3 half = glm::normalize(l + v);
        glm::dvec3 sum(0.0);
        for (const ViewHit& h : hits) {
          if (!h.hit) continue;
          const double cos_l = glm::dot(h.normal, l);
          if (cos_l <= 0.0) continue;
          if (Shadowed(grid, h.position, l, step)) continue;
          const double th = glm::dot(h.tangent, half);
          const double sin_th = std::sqrt(std::max(0.0, 1.0 - th * th));
          const glm::dvec3 tint = 0.5 * (glm::dvec3(1.0) + h.colour);
          sum +=
              cos_l * (h.colour / kPi +
                       gloss_norm * std::pow(sin_th, kGlossyExponent) * tint);
        }
        TableRow& row =
            table.rows[(static_cast<size_t>(texel) * pairs + view) * pairs +
                       light];
        row.wi = l;
        row.wo = v;
        row.value = sum / static_cast<double>(subsamples);
        row.sigma = glm::dvec3(1.0);
        row.weight = 1.0;
        row.s = s;
        row.t = t;
        row.alpha = alpha;
      }
    }
    // The texel's average normal over the hits of all its views (the
    // paper's Section 4: normals summed per sampling point, averaged at
    // the end); +z where no view ray hits.
    const glm::dvec3 normal = glm::length(normal_sum) > 0.0
                                  ? glm::normalize(normal_sum)
                                  : glm::dvec3(0.0, 0.0, 1.0);
    const size_t first = static_cast<size_t>(texel) * pairs * pairs;
    for (size_t i = first; i < first + static_cast<size_t>(pairs) * pairs;
         ++i) {
      table.rows[i].normal = normal;
    }
  };

  int workers = options.threads > 0
                    ? options.threads
                    : static_cast<int>(std::thread::hardware_concurrency());
  workers = std::max(1, std::min(workers, texel_count));
  std::atomic<int> next{0};
  auto work = [&]() {
    for (int texel = next++; texel < texel_count; texel = next++) {
      measure_texel(texel);
    }
  };
  if (workers == 1) {
    work();
  } else {
    std::vector<std::thread> pool;
    pool.reserve(workers - 1);
    for (int w = 1; w < workers; ++w) pool.emplace_back(work);
    work();
    for (std::thread& thread : pool) thread.join();
  }

  const std::string pattern = WeavePatternName(options.pattern);
  std::ostringstream sample;
  sample << "virtual gonioreflectometer: " << pattern
         << (options.pattern == WeavePattern::kKnit ? "" : " weave") << ", "
         << s_count << "x" << s_count << " texels, " << n << "x" << n
         << " directions, seed " << options.seed;
  table.SetMeta("sample", sample.str());
  table.SetMeta("pattern", pattern);
  table.SetMeta("texels", std::to_string(s_count));
  table.SetMeta("directions", std::to_string(n));
  table.SetMeta("seed", std::to_string(options.seed));
  table.SetMeta("supersample", std::to_string(k));
  table.SetMeta("thread_radius", FormatNumber(options.thread_radius));
  table.SetMeta("gap", FormatNumber(options.gap));
  table.SetMeta("glossy", FormatNumber(options.glossy));
  table.SetMeta("row_order", "t, s, view, light");
  return table;
}

}  // namespace clothfit
