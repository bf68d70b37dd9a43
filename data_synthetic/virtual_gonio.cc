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
#include <cstdio>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <limits>
#include <mutex>
#include <sstream>
#include <thread>
#include <vector>

#include "data_synthetic/synthetic_table.h"
#include "data_synthetic/weave_surface_internal.h"
#include "io/input_error.h"
#include "io/text_util.h"
#include "models/math.h"

namespace clothfit {
namespace {

using namespace weave_internal;  // NOLINT: the gonioreflectometer's geometry

// Directions stay within 85 degrees of the normal (the lowest stratum
// starts there).
const double kMinCosTheta = std::cos(Radians(85.0));

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
  // s^2 n^4 rows of about 180 bytes each are held in memory.
  const double rows =
      std::pow(double(o.texels), 2) * std::pow(double(o.directions), 4);
  if (rows > kMaxVirtualGonioRows) {
    char what[200];
    std::snprintf(what, sizeof(what),
                  "texels %d and directions %d make %.0f rows (texels^2 x "
                  "directions^4), more than %.0f (about 6.4 GB in memory)",
                  o.texels, o.directions, rows, kMaxVirtualGonioRows);
    fail(what);
  }
  if (o.supersample < 1) fail("supersample must be >= 1");
  if (o.grid < 16) fail("grid must be >= 16");
  if (o.threads < 0) fail("threads must be >= 0");
  if (!(o.thread_radius > 0.0) || !std::isfinite(o.thread_radius)) {
    fail("thread_radius must be > 0");
  }
  if (!(o.gap >= 0.0 && o.gap < kReferencePitch)) {
    fail("gap must be in [0, 0.5)");
  }
  if (!(o.glossy >= 0.0 && o.glossy <= 1.0)) {
    fail("glossy must be in [0, 1]");
  }
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
  const double diffuse_weight = 1.0 - options.glossy;
  const double gloss_norm = options.glossy / kGlossyBandAlbedo;

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
              cos_l * (diffuse_weight * h.colour / kPi +
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
  int done = 0;
  std::mutex progress_mutex;
  auto work = [&]() {
    for (int texel = next++; texel < texel_count; texel = next++) {
      measure_texel(texel);
      if (options.progress) {
        std::lock_guard<std::mutex> lock(progress_mutex);
        options.progress(++done, texel_count);
      }
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
  table.SetMeta("thread_radius",
                text_util::FormatNumber(options.thread_radius, 6));
  table.SetMeta("gap", text_util::FormatNumber(options.gap, 6));
  table.SetMeta("glossy", text_util::FormatNumber(options.glossy, 6));
  table.SetMeta("row_order", "t, s, view, light");
  return table;
}

}  // namespace clothfit
