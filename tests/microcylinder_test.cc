// Thread BSDF and cloth patch (models/microcylinder_*.h, docs/models.md-3.2).
#include <ceres/jet.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "models/evaluate.h"
#include "models/presets.h"
#include "tests/conformance_util.h"
#include "tests/direction_util.h"

namespace clothfit {
namespace {

using testing_util::Dir;
using testing_util::Preset;

// Every row of the independent implementation's output (docs/models.md).
TEST(MicrocylinderConformance, MatchesIndependentImplementation) {
  int rows = 0;
  for (const testing_util::ConformanceRow& row :
       testing_util::ReadConformanceRows()) {
    const glm::dvec3 rho = ClothRho(Preset(row.preset), row.wi, row.wo);
    for (int c = 0; c < 3; ++c) {
      const double ref = row.rho[c];
      EXPECT_NEAR(rho[c], ref, 1e-6 * std::abs(ref) + 1e-300)
          << row.preset << " row " << rows + 2 << " channel " << c;
    }
    ++rows;
  }
  EXPECT_EQ(rows, 300);
}

using Jet7 = ceres::Jet<double, kThreadFlatSize>;

ThreadParamsT<Jet7> SeedThread(const ThreadParams& p) {
  double x[kThreadFlatSize];
  ToArray(p, x);
  Jet7 j[kThreadFlatSize];
  for (int i = 0; i < kThreadFlatSize; ++i) j[i] = Jet7(x[i], i);
  ThreadParamsT<Jet7> out;
  FromArray(j, &out);
  return out;
}

ThreadParams ThreadFromArray(const double* x) {
  ThreadParams p;
  FromArray(x, &p);
  return p;
}

// A cloth's numbers as one list - per thread its coverage, its thread
// parameters (the table's order) and its tangent offsets - and back, for
// derivative checks over every entry.
int EntryCount(const ClothParams& c) {
  int n = 0;
  for (const ClothThread& th : c.threads) {
    n += 1 + kThreadFlatSize + static_cast<int>(th.offsets_deg.size());
  }
  return n + 4;  // rotation_deg, diffuse
}

std::vector<double> Entries(const ClothParams& c) {
  std::vector<double> x;
  for (const ClothThread& th : c.threads) {
    x.push_back(th.coverage);
    double p[kThreadFlatSize];
    ToArray(th.params, p);
    x.insert(x.end(), p, p + kThreadFlatSize);
    x.insert(x.end(), th.offsets_deg.begin(), th.offsets_deg.end());
  }
  x.push_back(c.rotation_deg);
  for (int k = 0; k < 3; ++k) x.push_back(c.diffuse[k]);
  return x;
}

template <typename T>
ClothParamsT<T> ClothFromEntries(const T* x, const ClothParams& layout) {
  ClothParamsT<T> c;
  for (const ClothThread& th : layout.threads) {
    ClothThreadT<T> out;
    out.direction = th.direction;
    out.coverage = *x++;
    FromArray(x, &out.params);
    x += kThreadFlatSize;
    out.offsets_deg.assign(x, x + th.offsets_deg.size());
    x += th.offsets_deg.size();
    c.threads.push_back(out);
  }
  c.rotation_deg = x[0];
  c.diffuse = Vec3<T>(x[1], x[2], x[3]);
  return c;
}

TEST(ThreadBsdf, JetAndDoubleAgreeAndGradientMatchesFiniteDifferences) {
  ThreadParams p;
  p.eta = 1.5;
  p.kd = 0.25;
  p.gamma_s_deg = 9.0;
  p.gamma_v_deg = 21.0;
  p.albedo = {0.3, 0.5, 0.7};
  const ThreadParamsT<Jet7> pj = SeedThread(p);
  const std::vector<std::pair<glm::dvec3, glm::dvec3>> pairs = {
      {Dir(30, 10), Dir(40, 200)},
      {Dir(70, -40), Dir(120, 60)},
      {Dir(5, 0), Dir(85, 180)},
      {Dir(89.9, 90), Dir(60, -90)}};
  for (const auto& [wi, wo] : pairs) {
    for (Quantity q : {Quantity::kBrdf, Quantity::kCosineWeighted}) {
      const glm::dvec3 f = Value(p, wi, wo, q);
      const Vec3<Jet7> fj = Value(pj, Cast<Jet7>(wi), Cast<Jet7>(wo), q);
      for (int c = 0; c < 3; ++c) {
        // Equal up to rounding: Ceres divides as a * (1 / b).
        EXPECT_NEAR(fj[c].a, f[c], 1e-12 * std::abs(f[c]));
        for (int k = 0; k < kThreadFlatSize; ++k) {
          double x[kThreadFlatSize];
          ToArray(p, x);
          const double h = 1e-6 * std::max(1.0, std::abs(x[k]));
          x[k] += h;
          const double up = Value(ThreadFromArray(x), wi, wo, q)[c];
          x[k] -= 2 * h;
          const double down = Value(ThreadFromArray(x), wi, wo, q)[c];
          const double fd = (up - down) / (2 * h);
          EXPECT_NEAR(fj[c].v[k], fd, 1e-5 * (std::abs(fd) + std::abs(f[c])))
              << "parameter " << FlatNames(ThreadParams())[k] << " channel "
              << c;
        }
      }
    }
  }
}

TEST(ClothRho, JetAndDoubleAgreeAndGradientMatchesFiniteDifferences) {
  using J = ceres::Jet<double, 1>;
  for (const char* name :
       {"polyester_satin_charmeuse", "silk_shot", "linen_plain"}) {
    ClothParams cloth = Preset(name);
    cloth.rotation_deg = 17.0;  // the optional freedoms too
    cloth.diffuse = glm::dvec3(0.05, 0.1, 0.15);
    const int n = EntryCount(cloth);
    const std::vector<double> x = Entries(cloth);
    for (const auto& [wi, wo] : {std::pair{Dir(35, 20), Dir(50, 190)},
                                 std::pair{Dir(60, 95), Dir(20, -80)}}) {
      const glm::dvec3 rho = ClothRho(cloth, wi, wo);
      for (int k = 0; k < n; ++k) {
        std::vector<J> xj(n);
        for (int i = 0; i < n; ++i) xj[i] = J(x[i]);
        xj[k].v[0] = 1.0;
        const Vec3<J> rj = ClothRho(ClothFromEntries(xj.data(), cloth),
                                    Cast<J>(wi), Cast<J>(wo));
        std::vector<double> xp = x, xm = x;
        const double h = 1e-6 * std::max(1.0, std::abs(x[k]));
        xp[k] += h;
        xm[k] -= h;
        const glm::dvec3 up =
            ClothRho(ClothFromEntries(xp.data(), cloth), wi, wo);
        const glm::dvec3 down =
            ClothRho(ClothFromEntries(xm.data(), cloth), wi, wo);
        for (int c = 0; c < 3; ++c) {
          EXPECT_NEAR(rj[c].a, rho[c], 1e-12 * rho[c]);
          const double fd = (up[c] - down[c]) / (2 * h);
          EXPECT_NEAR(rj[c].v[0], fd, 1e-5 * (std::abs(fd) + rho[c]))
              << name << " entry " << k << " channel " << c;
        }
      }
    }
  }
}

// A dense grid including exactly grazing and exactly normal directions, and
// directions along the thread tangents (zero-length projections).
std::vector<glm::dvec3> GridDirections() {
  std::vector<glm::dvec3> out;
  for (double theta :
       {0.0, 1e-9, 10.0, 30.0, 45.0, 60.0, 75.0, 85.0, 89.0, 89.999, 90.0}) {
    for (double phi = 0.0; phi < 360.0; phi += 15.0) {
      out.push_back(Dir(theta, phi));
      if (theta == 0.0) break;
    }
  }
  return out;
}

TEST(ClothRho, FiniteAndNonNegativeOverDenseGridIncludingGrazing) {
  const std::vector<glm::dvec3> dirs = GridDirections();
  for (const std::string& name : PresetNames()) {
    const ClothParams cloth = Preset(name);
    for (const glm::dvec3& wi : dirs) {
      for (const glm::dvec3& wo : dirs) {
        for (Quantity q : {Quantity::kBrdf, Quantity::kCosineWeighted}) {
          const glm::dvec3 v = Value(cloth, wi, wo, q);
          for (int c = 0; c < 3; ++c) {
            ASSERT_TRUE(std::isfinite(v[c]) && v[c] >= 0.0)
                << name << " wi " << wi.x << "," << wi.y << "," << wi.z
                << " wo " << wo.x << "," << wo.y << "," << wo.z << " -> "
                << v[c];
          }
        }
      }
    }
  }
}

TEST(ClothRho, GradientFiniteAtGrazingAndAlongTangents) {
  using J = ceres::Jet<double, 1>;
  const ClothParams cloth = Preset("velvet");  // tangents at -90 deg: +-z
  const int n = EntryCount(cloth);
  const std::vector<double> x = Entries(cloth);
  for (const glm::dvec3& wi : {Dir(0, 0), Dir(90, 0), Dir(89.999, 45)}) {
    for (const glm::dvec3& wo : {Dir(0, 0), Dir(90, 90), Dir(45, 180)}) {
      for (int k = 0; k < n; ++k) {
        std::vector<J> xj(x.begin(), x.end());
        xj[k].v[0] = 1.0;
        const Vec3<J> r = Value(ClothFromEntries(xj.data(), cloth), Cast<J>(wi),
                                Cast<J>(wo), Quantity::kBrdf);
        for (int c = 0; c < 3; ++c) {
          ASSERT_TRUE(std::isfinite(r[c].a) && std::isfinite(r[c].v[0]));
        }
      }
    }
  }
}

TEST(ThreadBsdf, FiniteAndNonNegativeOverTheWholeSphere) {
  ThreadParams p;
  std::vector<glm::dvec3> dirs = GridDirections();
  const size_t upper = dirs.size();
  for (size_t i = 0; i < upper; ++i) dirs.push_back(-dirs[i]);
  dirs.push_back({1, 0, 0});  // along the tangent: no azimuth
  dirs.push_back({-1, 0, 0});
  for (const glm::dvec3& wi : dirs) {
    for (const glm::dvec3& wo : dirs) {
      const glm::dvec3 f = ThreadBsdfLocal(p, wi, wo);
      for (int c = 0; c < 3; ++c) {
        ASSERT_TRUE(std::isfinite(f[c]) && f[c] >= 0.0);
      }
    }
  }
  // A direction along the tangent contributes nothing (docs/models.md).
  EXPECT_EQ(ThreadBsdfLocal(p, glm::dvec3(1, 0, 0), Dir(30, 0)).x, 0.0);
}

TEST(ThreadBsdf, SpecularConeOfTheTangent) {
  // For a thread along +x the surface reflection peaks where
  // theta_o = -theta_i, i.e. wo on the cone around the tangent mirroring wi.
  // A narrow lobe keeps the 1/cos^2(theta_d) and Fresnel factors from
  // shifting the peak by more than a few hundredths of a degree.
  ThreadParams p;
  p.gamma_s_deg = 0.5;
  p.kd = 0.0;
  p.albedo = glm::dvec3(0.0);
  const glm::dvec3 wi = Dir(50, 0);  // 40 deg from the tangent
  double best = -1.0, best_theta = 0.0;
  for (double theta_o = -89.5; theta_o <= 89.5; theta_o += 0.05) {
    // Viewer in the plane y = 0 on the far side of the normal.
    const double t = Radians(theta_o);
    const glm::dvec3 wo(std::sin(t), 0.0, std::cos(t));
    const double f = ThreadBsdfLocal(p, wi, wo).x;
    if (f > best) best = f, best_theta = theta_o;
  }
  EXPECT_NEAR(best_theta, -50.0, 0.11);
}

// The front of the satin has flat tangent segments at +-32 deg (and +-18,
// 0) along u: with the light at normal incidence in the xz plane, each tilt
// psi mirrors the light to theta_o = 2 psi, so the off-specular highlight
// pair sits at +-64 deg (the +-18 pair at +-36 deg), with dips between.
TEST(ClothRho, SatinShowsItsOffSpecularHighlightPair) {
  const ClothParams satin = Preset("polyester_satin_charmeuse");
  const glm::dvec3 wi(0, 0, 1);
  std::vector<double> angle, value;
  for (double t = -89.0; t <= 89.0; t += 0.5) {
    angle.push_back(t);
    value.push_back(ClothRho(satin, wi, Dir(std::abs(t), t < 0 ? 180 : 0)).y);
  }
  std::vector<double> maxima;
  for (size_t i = 1; i + 1 < value.size(); ++i) {
    if (value[i] > value[i - 1] && value[i] >= value[i + 1]) {
      maxima.push_back(angle[i]);
    }
  }
  auto has_peak_near = [&](double where) {
    for (double m : maxima) {
      if (std::abs(m - where) <= 2.0) return true;
    }
    return false;
  };
  EXPECT_TRUE(has_peak_near(64.0));
  EXPECT_TRUE(has_peak_near(-64.0));
  EXPECT_TRUE(has_peak_near(36.0));
  EXPECT_TRUE(has_peak_near(-36.0));
  auto at = [&](double t) {
    return ClothRho(satin, wi, Dir(std::abs(t), t < 0 ? 180 : 0)).y;
  };
  EXPECT_GT(at(64.0), 3.0 * at(50.0));
  EXPECT_NEAR(at(64.0), at(-64.0), 1e-12);
  // Along v the flat threads show no such pair: no peak near +-64 deg.
  const double along_v = ClothRho(satin, wi, Dir(64.0, 90.0)).y;
  EXPECT_LT(along_v, 0.5 * at(64.0));
}

TEST(ClothRho, ReflectionOnly) {
  const ClothParams c = Preset("linen_plain");
  EXPECT_EQ(ClothRho(c, Dir(30, 0), -Dir(30, 0)).x, 0.0);
  EXPECT_EQ(ClothRho(c, -Dir(30, 0), Dir(30, 0)).x, 0.0);
  EXPECT_GT(ClothRho(c, Dir(30, 0), Dir(30, 180)).x, 0.0);
}

// rotation_deg turns the weave about the normal: the same as turning both
// directions the other way; a quarter turn makes a warp (u) a weft (v).
TEST(ClothRho, RotationTurnsTheWeaveAboutTheNormal) {
  const ClothParams linen = Preset("linen_plain");
  ClothParams turned = linen;
  turned.rotation_deg = 30.0;
  auto rotate = [](const glm::dvec3& w, double deg) {
    const double r = Radians(deg);
    return glm::dvec3(std::cos(r) * w.x - std::sin(r) * w.y,
                      std::sin(r) * w.x + std::cos(r) * w.y, w.z);
  };
  ClothParams one_u = linen, one_v = linen;
  one_u.threads.resize(1);
  one_v.threads.resize(1);
  one_v.threads[0].direction = ThreadDirection::kV;
  one_u.rotation_deg = 90.0;
  for (const auto& [wi, wo] : {std::pair{Dir(35, 20), Dir(50, 190)},
                               std::pair{Dir(70, 95), Dir(20, -80)},
                               std::pair{Dir(80, 0), Dir(82, 170)}}) {
    const glm::dvec3 a = ClothRho(turned, wi, wo);
    const glm::dvec3 b = ClothRho(linen, rotate(wi, -30.0), rotate(wo, -30.0));
    const glm::dvec3 c = ClothRho(one_u, wi, wo);
    const glm::dvec3 d = ClothRho(one_v, wi, wo);
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(a[k], b[k], 1e-12 * b[k]);
      EXPECT_NEAR(c[k], d[k], 1e-12 * d[k]);
    }
  }
  // A turn that is not a symmetry of the weave changes the value.
  EXPECT_GT(std::abs(ClothRho(turned, Dir(60, 0), Dir(60, 180)).y -
                     ClothRho(linen, Dir(60, 0), Dir(60, 180)).y),
            1e-3 * ClothRho(linen, Dir(60, 0), Dir(60, 180)).y);
}

// diffuse adds a Lambertian f = diffuse / pi outside the normalisation.
TEST(ClothRho, DiffuseAddsALambertianTerm) {
  const ClothParams linen = Preset("linen_plain");
  ClothParams with = linen;
  with.diffuse = glm::dvec3(0.1, 0.2, 0.3);
  for (const auto& [wi, wo] : {std::pair{Dir(35, 20), Dir(50, 190)},
                               std::pair{Dir(89.9, 95), Dir(20, -80)}}) {
    const glm::dvec3 extra = ClothRho(with, wi, wo) - ClothRho(linen, wi, wo);
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(extra[k], with.diffuse[k] * wi.z / kPi, 1e-15);
    }
  }
  // Alone (no coverage): the Lambertian term, not 0.
  ClothParams bare = with;
  for (ClothThread& th : bare.threads) th.coverage = 0.0;
  EXPECT_NEAR(ClothRho(bare, Dir(40, 0), Dir(30, 90)).z,
              0.3 * std::cos(Radians(40.0)) / kPi, 1e-15);
  EXPECT_EQ(ClothRho(with, Dir(40, 0), -Dir(30, 90)).x, 0.0);  // reflection
}

TEST(ClothRho, NoCoverageGivesZeroNotNaN) {
  ClothParams c = Preset("linen_plain");
  for (ClothThread& th : c.threads) th.coverage = 0.0;
  const glm::dvec3 rho = ClothRho(c, Dir(30, 0), Dir(40, 100));
  EXPECT_EQ(rho.x, 0.0);
}

TEST(ThreadParams, ArrayRoundTrip) {
  ThreadParams p;
  p.eta = 1.3;
  p.kd = 0.4;
  p.gamma_s_deg = 7;
  p.gamma_v_deg = 11;
  p.albedo = {0.1, 0.2, 0.3};
  double x[kThreadFlatSize];
  ToArray(p, x);
  const ThreadParams q = ThreadFromArray(x);
  EXPECT_EQ(q.eta, p.eta);
  EXPECT_EQ(q.kd, p.kd);
  EXPECT_EQ(q.gamma_s_deg, p.gamma_s_deg);
  EXPECT_EQ(q.gamma_v_deg, p.gamma_v_deg);
  EXPECT_EQ(q.albedo, p.albedo);
}

TEST(Validation, NamesTheField) {
  ThreadParams p;
  p.gamma_s_deg = -1;
  EXPECT_NE(ValidateParams(p).find("gamma_s_deg"), std::string::npos);
  p = ThreadParams();
  p.eta = 1.0;
  EXPECT_NE(ValidateParams(p).find("eta"), std::string::npos);
  ClothParams c = Preset("linen_plain");
  c.threads[0].coverage = 0.8;
  EXPECT_NE(ValidateClothParams(c).find("sum"), std::string::npos);
  c = Preset("linen_plain");
  c.threads[1].params.kd = 2;
  EXPECT_NE(ValidateClothParams(c).find("threads[1].kd"), std::string::npos);
  for (const std::string& name : PresetNames()) {
    EXPECT_EQ(ValidateClothParams(Preset(name)), "") << name;
  }
}

TEST(TangentCurve, SamplesEquidistantAlongLength) {
  TangentCurve c;
  c.offsets_deg = {-30, 30};
  c.lengths = {1};
  c.samples = 4;  // at 1/8, 3/8, 5/8, 7/8 of the length
  const std::vector<double> s = SampleTangentCurve(c);
  ASSERT_EQ(s.size(), 4u);
  EXPECT_NEAR(s[0], -22.5, 1e-12);
  EXPECT_NEAR(s[1], -7.5, 1e-12);
  EXPECT_NEAR(s[2], 7.5, 1e-12);
  EXPECT_NEAR(s[3], 22.5, 1e-12);
}

TEST(TangentCurve, ZeroLengthSegmentIsAJump) {
  TangentCurve c;  // velvet's v thread: -90..-55, jump, 55..90
  c.offsets_deg = {-90, -55, 55, 90};
  c.lengths = {0.5, 0, 0.5};
  c.samples = 2;  // at 0.25 and 0.75
  const std::vector<double> s = SampleTangentCurve(c);
  ASSERT_EQ(s.size(), 2u);
  EXPECT_NEAR(s[0], -72.5, 1e-12);
  EXPECT_NEAR(s[1], 72.5, 1e-12);
  EXPECT_EQ(ValidateTangentCurve(c), "");
  c.lengths = {1};
  EXPECT_NE(ValidateTangentCurve(c).find("curve_lengths"), std::string::npos);
}

TEST(TangentCurve, DenseSamplingFollowsTheFlatSegments) {
  // Sampling the satin curve densely puts most samples on the flat parts.
  ClothParams satin = Preset("polyester_satin_charmeuse");
  TangentCurve c = satin.threads[0].curve;
  c.samples = 1000;
  ASSERT_EQ(ValidateTangentCurve(c), "");
  const std::vector<double> s = SampleTangentCurve(c);
  int at_32 = 0;
  for (double o : s) at_32 += std::abs(std::abs(o) - 32.0) < 1e-9;
  // The two flat +-32 segments are 2 * 1.33 of the total length 9.98.
  EXPECT_NEAR(at_32 / 1000.0, 2.66 / 9.98, 0.002);
}

}  // namespace
}  // namespace clothfit
