// The optically thin slab (models/slab.h, docs/models.md): closed-form limits,
// reciprocity, the series around mu_o = mu_i, grazing directions,
// derivatives, parameter checks and the multiple-scattering estimate.
#include <ceres/jet.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "models/evaluate.h"
#include "models/slab.h"
#include "tests/direction_util.h"

namespace clothfit {
namespace {

using testing_util::Dir;

constexpr double kC = 1.0 / (4.0 * kPi);  // the phase function's A / (4 pi)

SlabParams Slab(const glm::dvec3& tau, const glm::dvec3& albedo) {
  SlabParams p;
  p.tau = tau;
  p.albedo = albedo;
  return p;
}

SlabParams Slab(double tau, const glm::dvec3& albedo) {
  return Slab(glm::dvec3(tau), albedo);
}

void ExpectRel(double actual, double expected, double tolerance,
               const std::string& where) {
  EXPECT_LE(std::abs(actual - expected), tolerance * std::abs(expected))
      << where << ": " << actual << " vs " << expected;
}

TEST(SlabParams, ArrayRoundTrip) {
  const SlabParams p = Slab({0.1, 0.2, 0.3}, {0.9, 0.8, 0.7});
  ASSERT_EQ(FlatSize(p), 6);
  double x[6];
  ToArray(p, x);
  SlabParams q;
  FromArray(x, &q);
  EXPECT_EQ(q.tau, p.tau);
  EXPECT_EQ(q.albedo, p.albedo);
  EXPECT_EQ(FlatNames(p)[0], "tau_r");
  EXPECT_EQ(FlatNames(p)[5], "albedo_b");
}

TEST(SlabParams, RangesAreCheckedWithTheFieldName) {
  EXPECT_EQ(ValidateParams(Slab(0.5, glm::dvec3(0.9))), "");
  EXPECT_EQ(ValidateParams(Slab(0.5, glm::dvec3(0.0))), "");
  EXPECT_EQ(ValidateParams(Slab(0.5, glm::dvec3(1.0))), "");
  for (double tau : {0.0, -0.1, std::nan(""), HUGE_VAL}) {
    const std::string e = ValidateParams(Slab(tau, glm::dvec3(0.5)));
    EXPECT_EQ(e.rfind("tau:", 0), 0u) << tau << ": " << e;
    EXPECT_NE(e.find("[1e-12, 10000]"), std::string::npos) << e;
  }
  const SlabParams p = Slab({0.5, 0.5, 0.0}, glm::dvec3(0.5));
  EXPECT_NE(ValidateParams(p).find("component 2"), std::string::npos);
  for (double a : {1.0001, -0.01, std::nan("")}) {
    const std::string e = ValidateParams(Slab(0.5, {0.5, a, 0.5}));
    EXPECT_EQ(e.rfind("albedo:", 0), 0u) << a << ": " << e;
    EXPECT_NE(e.find("component 1"), std::string::npos) << e;
  }
}

// tau -> 0: one scattering per unit optical path and no attenuation, so
// f_r = f_t = A/(4 pi) tau / (mu_i mu_o) to first order, and D = 1 - tau/mu.
TEST(SlabModel, ThinLimit) {
  const double tau = 1e-9;
  const SlabParams p = Slab(tau, {0.9, 0.5, 0.1});
  for (double mu_i : {1.0, 0.6, 0.2}) {
    for (double mu_o : {1.0, 0.6, 0.2, 0.6000001}) {
      const std::string where =
          std::to_string(mu_i) + "," + std::to_string(mu_o);
      const glm::dvec3 fr = SlabReflection(p, mu_i, mu_o);
      const glm::dvec3 ft = SlabTransmission(p, mu_i, mu_o);
      for (int c = 0; c < 3; ++c) {
        const double thin = p.albedo[c] * kC * tau / (mu_i * mu_o);
        ExpectRel(fr[c], thin, 1e-8, "f_r " + where);
        ExpectRel(ft[c], thin, 1e-8, "f_t " + where);
      }
    }
    ExpectRel(DirectTransmittance(tau, mu_i), 1.0 - tau / mu_i, 1e-15, "D");
  }
}

// tau -> infinity: reflection is the Lommel-Seeliger law, nothing passes.
TEST(SlabModel, ThickLimitIsLommelSeeliger) {
  const SlabParams p = Slab(1e3, {0.9, 0.5, 0.1});
  for (double mu_i : {1.0, 0.5, 0.05}) {
    for (double mu_o : {1.0, 0.5, 0.05}) {
      const glm::dvec3 fr = SlabReflection(p, mu_i, mu_o);
      const glm::dvec3 ft = SlabTransmission(p, mu_i, mu_o);
      for (int c = 0; c < 3; ++c) {
        ExpectRel(fr[c], p.albedo[c] / (4.0 * kPi) / (mu_i + mu_o), 1e-15,
                  "f_r");
        EXPECT_LT(ft[c], 1e-300);
      }
    }
    EXPECT_LT(DirectTransmittance(1e3, mu_i), 1e-300);
  }
}

// docs/models.md's forms, written out here in long double (the reference).
long double RefReflection(long double tau, long double mi, long double mo) {
  return (1.0L - std::exp(-tau * (1.0L / mi + 1.0L / mo))) / (mi + mo);
}
long double RefTransmission(long double tau, long double mi, long double mo) {
  if (mi == mo) return tau / (mi * mi) * std::exp(-tau / mi);
  return (std::exp(-tau / mo) - std::exp(-tau / mi)) / (mo - mi);
}

TEST(SlabModel, MatchesSpecFormulasAwayFromTheSingularity) {
  for (double tau : {0.01, 0.3, 2.0}) {
    for (double mu_i : {0.95, 0.5, 0.15}) {
      for (double mu_o : {0.9, 0.4, 0.1}) {
        const std::string where = std::to_string(tau);
        ExpectRel(SlabReflectionFactor(tau, mu_i, mu_o),
                  RefReflection(tau, mu_i, mu_o), 1e-14, "f_r " + where);
        ExpectRel(SlabTransmissionFactor(tau, mu_i, mu_o),
                  RefTransmission(tau, mu_i, mu_o), 1e-13, "f_t " + where);
      }
    }
  }
  // mu_o = mu_i: the model's limit tau / mu^2 exp(-tau / mu).
  for (double mu : {1.0, 0.3, 0.02}) {
    ExpectRel(SlabTransmissionFactor(0.4, mu, mu), RefTransmission(0.4, mu, mu),
              1e-14, "f_t diagonal");
  }
}

TEST(SlabModel, Reciprocity) {
  const SlabParams p = Slab({0.05, 0.3, 1.7}, {0.9, 0.6, 0.3});
  const std::vector<glm::dvec3> dirs = {
      Dir(0, 0),    Dir(25, 40),   Dir(60, 200), Dir(85, 10),
      Dir(120, 70), Dir(170, 300), Dir(95, 5)};
  for (const glm::dvec3& a : dirs) {
    for (const glm::dvec3& b : dirs) {
      const glm::dvec3 ab = SlabBsdf(p, a, b);
      const glm::dvec3 ba = SlabBsdf(p, b, a);
      for (int c = 0; c < 3; ++c) ExpectRel(ab[c], ba[c], 1e-15, "f(a,b)");
      EXPECT_EQ(SlabTransmits(a, b), a.z * b.z < 0.0);
    }
  }
}

using Jet3 = ceres::Jet<double, 3>;

// f_t / (A/4pi) and its derivatives by tau, mu_i, mu_o in long double, from
// the divided difference (well conditioned where |mu_o - mu_i| is not tiny).
void RefTransmissionGradient(long double tau, long double mi, long double mo,
                             long double* value, long double grad[3]) {
  const long double hi = std::exp(-tau / mi), ho = std::exp(-tau / mo);
  const long double d = mo - mi;
  *value = (ho - hi) / d;
  grad[0] = (-ho / mo + hi / mi) / d;
  grad[1] = -(tau / (mi * mi) * hi) / d + (ho - hi) / (d * d);
  grad[2] = (tau / (mo * mo) * ho) / d - (ho - hi) / (d * d);
}

// Across the switch between the series (y < 0.25) and the closed form: the
// value and all three derivatives agree with the reference to 1e-12.
TEST(SlabModel, SeriesSwitchIsAccurateInValueAndDerivatives) {
  for (double tau : {0.05, 0.5, 3.0}) {
    for (double mu_i : {0.9, 0.4, 0.1}) {
      // mu_o at y = tau (1/mu_o - 1/mu_i) = 0.25 (1 + s), both sides.
      for (double s : {-0.2, -1e-3, -1e-9, 1e-9, 1e-3, 0.2}) {
        const double y = kSlabSeriesSwitch * (1.0 + s);
        const double mu_o = 1.0 / (1.0 / mu_i + y / tau);
        const Jet3 ft =
            SlabTransmissionFactor(Jet3(tau, 0), Jet3(mu_i, 1), Jet3(mu_o, 2));
        long double ref, grad[3];
        RefTransmissionGradient(tau, mu_i, mu_o, &ref, grad);
        const std::string where = "tau " + std::to_string(tau) + " mu_i " +
                                  std::to_string(mu_i) + " s " +
                                  std::to_string(s);
        ExpectRel(ft.a, static_cast<double>(ref), 1e-12, where);
        for (int k = 0; k < 3; ++k) {
          ExpectRel(ft.v[k], static_cast<double>(grad[k]), 1e-12,
                    where + " d" + std::to_string(k));
        }
      }
    }
  }
  // The two forms of the mean attenuation E(y) at the same points.
  for (double y : {0.05, 0.2, 0.24, 0.25, 0.26, 0.3}) {
    using Jet1 = ceres::Jet<double, 1>;
    const Jet1 series = MeanAttenuationSeries(Jet1(y, 0));
    const Jet1 closed = MeanAttenuationClosed(Jet1(y, 0));
    ExpectRel(series.a, closed.a, 1e-14, "E " + std::to_string(y));
    ExpectRel(series.v[0], closed.v[0], 1e-12, "E' " + std::to_string(y));
  }
}

// At mu_o = mu_i exactly and around it: smooth, finite, the model's limit.
TEST(SlabModel, SmoothThroughEqualCosines) {
  const double tau = 0.3, mu = 0.5;
  const Jet3 at =
      SlabTransmissionFactor(Jet3(tau, 0), Jet3(mu, 1), Jet3(mu, 2));
  const double e = std::exp(-tau / mu);
  ExpectRel(at.a, tau / (mu * mu) * e, 1e-15, "value");
  // d/dtau of tau/mu^2 exp(-tau/mu); by symmetry d/dmu_i = d/dmu_o = half
  // of d/dmu of tau/mu^2 exp(-tau/mu).
  ExpectRel(at.v[0], (1.0 / (mu * mu) - tau / (mu * mu * mu)) * e, 1e-14,
            "d tau");
  const double d_mu =
      (-2.0 * tau / (mu * mu * mu) + tau * tau / (mu * mu * mu * mu)) * e;
  ExpectRel(at.v[1], 0.5 * d_mu, 1e-14, "d mu_i");
  ExpectRel(at.v[2], 0.5 * d_mu, 1e-14, "d mu_o");
  // Neighbours within 1e-12 of the diagonal differ from it by O(1e-12).
  for (double d : {-1e-12, 1e-12}) {
    ExpectRel(SlabTransmissionFactor(tau, mu, mu + d), at.a, 1e-11, "near");
  }
}

TEST(SlabModel, GrazingLimitsAreFinite) {
  const double tau = 0.2, mu = 0.6;
  // mu_o -> 0: exp(-tau/mu_o) and all its derivatives vanish.
  ExpectRel(SlabReflectionFactor(tau, mu, 0.0), 1.0 / mu, 1e-15, "f_r");
  ExpectRel(SlabTransmissionFactor(tau, mu, 0.0), std::exp(-tau / mu) / mu,
            1e-15, "f_t");
  EXPECT_EQ(DirectTransmittance(tau, 0.0), 0.0);
  // Continuous into the limit.
  ExpectRel(SlabReflectionFactor(tau, mu, 1e-9), 1.0 / mu, 1e-8, "f_r 1e-9");
  ExpectRel(SlabTransmissionFactor(tau, mu, 1e-9), std::exp(-tau / mu) / mu,
            1e-8, "f_t 1e-9");
  // Jets stay finite at and near grazing, also with both directions there.
  for (double mu_o : {0.0, 1e-300, 1e-200, 1e-12, 1e-3}) {
    for (double mu_i : {mu, mu_o}) {
      const Jet3 r =
          SlabReflectionFactor(Jet3(tau, 0), Jet3(mu_i, 1), Jet3(mu_o, 2));
      const Jet3 t =
          SlabTransmissionFactor(Jet3(tau, 0), Jet3(mu_i, 1), Jet3(mu_o, 2));
      const Jet3 d = DirectTransmittance(Jet3(tau, 0), Jet3(mu_o, 2));
      for (const Jet3& j : {r, t, d}) {
        EXPECT_TRUE(std::isfinite(j.a)) << mu_i << " " << mu_o;
        for (int k = 0; k < 3; ++k) {
          EXPECT_TRUE(std::isfinite(j.v[k])) << mu_i << " " << mu_o;
        }
      }
    }
  }
}

constexpr int kSlabFlatSize = 6;
using Jet6 = ceres::Jet<double, kSlabFlatSize>;

SlabParams SlabFromArray(const double* x) {
  SlabParams p;
  FromArray(x, &p);
  return p;
}

TEST(SlabModel, JetGradientMatchesFiniteDifferences) {
  const SlabParams p = Slab({0.07, 0.4, 1.3}, {0.8, 0.5, 0.2});
  double x[kSlabFlatSize];
  ToArray(p, x);
  Jet6 xj[kSlabFlatSize];
  for (int i = 0; i < kSlabFlatSize; ++i) xj[i] = Jet6(x[i], i);
  SlabParamsT<Jet6> pj;
  FromArray(xj, &pj);
  for (const auto& [wi, wo] : std::vector<std::pair<glm::dvec3, glm::dvec3>>{
           {Dir(10, 0), Dir(50, 90)},
           {Dir(40, 0), Dir(140, 30)},
           {Dir(30, 0), Dir(150, 0)}}) {  // mu_o = mu_i
    for (Quantity q : {Quantity::kBrdf, Quantity::kCosineWeighted,
                       Quantity::kTransmittance}) {
      const Vec3<Jet6> f = Value(pj, wi, wo, q);
      const glm::dvec3 f0 = Value(p, wi, wo, q);
      for (int c = 0; c < 3; ++c) {
        ExpectRel(f[c].a, f0[c], 1e-14, "value");
        for (int i = 0; i < kSlabFlatSize; ++i) {
          double xp[kSlabFlatSize], xm[kSlabFlatSize];
          std::copy(x, x + kSlabFlatSize, xp);
          std::copy(x, x + kSlabFlatSize, xm);
          const double h = 1e-6 * x[i];
          xp[i] += h;
          xm[i] -= h;
          const double fd = (Value(SlabFromArray(xp), wi, wo, q)[c] -
                             Value(SlabFromArray(xm), wi, wo, q)[c]) /
                            (2.0 * h);
          EXPECT_NEAR(f[c].v[i], fd, 1e-7 * std::abs(f0[c]) / x[i] + 1e-14)
              << "channel " << c << " entry " << i;
        }
      }
    }
  }
}

TEST(SlabModel, EvaluateGivesEachQuantity) {
  const SlabParams p = Slab({0.1, 0.2, 0.4}, {0.9, 0.6, 0.3});
  const ModelParams model = p;
  EXPECT_TRUE(ModelPredicts(model, Quantity::kTransmittance));
  EXPECT_FALSE(
      ModelPredicts(ModelParams(ThreadParams()), Quantity::kTransmittance));
  const glm::dvec3 wi = Dir(30, 0), up = Dir(50, 120), down = Dir(130, 20);
  const double mu_i = wi.z, mu_up = up.z, mu_down = -down.z;
  const glm::dvec3 fr = Evaluate(model, wi, up, Quantity::kBrdf);
  const glm::dvec3 ft = Evaluate(model, wi, down, Quantity::kBrdf);
  const glm::dvec3 rho = Evaluate(model, wi, down, Quantity::kCosineWeighted);
  const glm::dvec3 d = Evaluate(model, wi, down, Quantity::kTransmittance);
  for (int c = 0; c < 3; ++c) {
    const double tau = p.tau[c], a = p.albedo[c];
    ExpectRel(fr[c], a * kC * RefReflection(tau, mu_i, mu_up), 1e-14, "f_r");
    ExpectRel(ft[c], a * kC * RefTransmission(tau, mu_i, mu_down), 1e-14,
              "f_t");
    ExpectRel(rho[c], ft[c] * mu_i, 1e-15, "rho");
    ExpectRel(d[c], std::exp(-tau / mu_down), 1e-15, "D");
  }
}

// q(tau) = 1 - (1/tau) int_0^1 mu (1 - exp(-tau/mu)) dmu by quadrature
// (Simpson in log mu, which resolves the transition at mu ~ tau).
double RescatterByQuadrature(double tau) {
  const int n = 20000;  // even
  const double lo = std::log(1e-14), hi = 0.0, h = (hi - lo) / n;
  double sum = 0.0;
  for (int k = 0; k <= n; ++k) {
    const double mu = std::exp(lo + k * h);
    const double f = mu * mu * -std::expm1(-tau / mu);  // dmu = mu ds
    sum += f * (k == 0 || k == n ? 1.0 : k % 2 == 1 ? 4.0 : 2.0);
  }
  return 1.0 - sum * h / 3.0 / tau;
}

TEST(SlabModel, RescatterProbabilityMatchesQuadrature) {
  for (double tau : {1e-4, 0.01, 0.05, 0.2, 1.0, 1.999, 2.001, 5.0, 30.0}) {
    ExpectRel(SlabRescatterProbability(tau), RescatterByQuadrature(tau), 1e-9,
              "q(" + std::to_string(tau) + ")");
  }
  // Known values from the exponential integrals (A&S Table 5.1):
  // E3(1) = 0.109692, so q(1) = 1 - (0.5 - 0.109692) = 0.609692.
  EXPECT_NEAR(SlabRescatterProbability(1.0), 0.609692, 1e-6);
  EXPECT_NEAR(SlabSingleScatterError(1.0, 0.5), 0.304846, 1e-6);
  const double q = SlabRescatterProbability(0.05);
  ExpectRel(SlabMultipleScatteringAlbedo(0.05, 0.9 / (1.0 - 0.9 * q)), 0.9,
            1e-12, "albedo correction inverts A / (1 - A q)");
}

}  // namespace
}  // namespace clothfit
