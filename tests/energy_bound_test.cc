// models/energy_bound.h: the bounded thread and cloth conserve energy on
// both sides over a dense hemisphere (grazing included), equal the paper's
// model where it conserves energy, and stay finite at the horizon.
#include "models/energy_bound.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "models/evaluate.h"
#include "models/presets.h"

namespace clothfit {
namespace {

glm::dvec3 Direction(double theta_deg, double phi_deg) {
  const double t = theta_deg * kPi / 180.0, p = phi_deg * kPi / 180.0;
  return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

// The largest albedo of either side, in any channel, at polar angles from
// the normal to 89.9 degrees (every 10 degrees of azimuth), by a quadrature
// of 48 rings: finer than the bound's own (16 and 32 rings).
template <typename P>
double LargestAlbedo(const P& p) {
  const HemisphereQuadrature q = MakeHemisphereQuadrature(48);
  double largest = 0.0;
  for (double theta : {0.0, 45.0, 70.0, 80.0, 85.0, 86.0, 87.0, 88.0, 89.9}) {
    for (int j = 0; j < 36; ++j) {
      const glm::dvec3 w = Direction(theta, 10.0 * j);
      glm::dvec3 light(0.0), view(0.0);
      for (size_t i = 0; i < q.w.size(); ++i) {
        light += q.weight[i] * q.w[i].z * Rho(p, w, q.w[i]) / w.z;
        view += q.weight[i] * Rho(p, q.w[i], w);
      }
      largest = std::max({largest, light.x, light.y, light.z, view.x, view.y,
                          view.z});
    }
  }
  return largest;
}

template <typename P>
std::shared_ptr<const EnergyBound> BoundOf(const P& p, double phi0 = 0.0) {
  return ComputeEnergyBound(
      [&](const glm::dvec3& wi, const glm::dvec3& wo) {
        return Rho(p, wi, wo);
      },
      phi0);
}

// Sadeghi et al.'s model reflects far more than it receives toward grazing
// (a cloth's light side, a thread's view side along its axis); bounded, it
// reflects at most what it receives everywhere. The satin's back is the
// preset closest to the bound's margin.
TEST(EnergyBound, BoundedPresetsConserveEnergyOnADenseHemisphere) {
  for (const std::string name :
       {"linen_plain", "polyester_satin_charmeuse_back", "velvet"}) {
    SCOPED_TRACE(name);
    ClothParams cloth;
    ASSERT_TRUE(GetPreset(name, &cloth));
    ThreadParams thread = cloth.threads[0].params;
    EXPECT_GT(LargestAlbedo(cloth), 10.0);
    EXPECT_GT(LargestAlbedo(thread), 2.0);
    cloth.energy_bound = BoundOf(cloth, cloth.rotation_deg * kPi / 180.0);
    thread.energy_bound = BoundOf(thread);
    ASSERT_NE(cloth.energy_bound, nullptr);
    ASSERT_NE(thread.energy_bound, nullptr);
    EXPECT_EQ(ValidateEnergyBound(*cloth.energy_bound), std::string());
    EXPECT_LE(LargestAlbedo(cloth), 1.0);
    EXPECT_LE(LargestAlbedo(thread), 1.0);
  }
}

// A dim thread conserves energy as it is: it needs no bound.
TEST(EnergyBound, AModelThatConservesEnergyNeedsNone) {
  ThreadParams dim;
  dim.scale = 0.05;
  ASSERT_LT(LargestAlbedo(dim), 0.9);
  EXPECT_EQ(BoundOf(dim), nullptr);
}

// Where both albedos are below 1 and both directions above 87 degrees from
// the normal the bounded cloth is the paper's, to the bit; at the horizon
// it fades to 0 and stays finite.
TEST(EnergyBound, BoundedModelIsThePapersWhereItConservesEnergy) {
  ClothParams paper;
  ASSERT_TRUE(GetPreset("linen_plain", &paper));
  ClothParams bounded = paper;
  bounded.energy_bound = BoundOf(paper);
  ASSERT_NE(bounded.energy_bound, nullptr);
  for (double ti : {0.0, 20.0, 40.0}) {
    for (double to : {0.0, 30.0, 45.0}) {
      const glm::dvec3 wi = Direction(ti, 10.0), wo = Direction(to, 200.0);
      EXPECT_EQ(Rho(bounded, wi, wo), Rho(paper, wi, wo)) << ti << " " << to;
    }
  }
  const glm::dvec3 normal(0.0, 0.0, 1.0);
  for (const glm::dvec3& grazing :
       {glm::dvec3(1.0, 0.0, 0.0), glm::dvec3(std::cos(0.3), std::sin(0.3),
                                              1e-12)}) {
    const glm::dvec3 a = Rho(bounded, grazing, normal);
    const glm::dvec3 b = Rho(bounded, normal, grazing);
    for (int c = 0; c < 3; ++c) {
      EXPECT_TRUE(std::isfinite(a[c]) && std::isfinite(b[c]));
      EXPECT_LE(std::abs(a[c]), 1e-9);
      EXPECT_LE(std::abs(b[c]), 1e-9);
    }
  }
  // The factor: 1 without a bound and below the surface, in [0, 1].
  EXPECT_EQ(EnergyBoundFactor<double>(nullptr, 0.5, 0.5), 1.0);
  EXPECT_EQ(EnergyBoundFactor(bounded.energy_bound.get(), -0.5, 0.5), 1.0);
  for (double ci : {1e-6, 0.01, 0.1, 0.5, 1.0}) {
    for (double co : {1e-6, 0.01, 0.1, 0.5, 1.0}) {
      const double f = EnergyBoundFactor(bounded.energy_bound.get(), ci, co);
      EXPECT_GE(f, 0.0);
      EXPECT_LE(f, 1.0);
    }
  }
}

TEST(EnergyBound, TablesThatCannotBeUsedAreRefused) {
  EnergyBound b;
  b.light = {0.1, 0.2};
  b.view = {1.0, 1.0};
  EXPECT_EQ(ValidateEnergyBound(b), std::string());
  b.view = {1.0};
  EXPECT_NE(ValidateEnergyBound(b), std::string());
  b.view = {1.0, -1.0};
  EXPECT_NE(ValidateEnergyBound(b), std::string());
  b.view = {1.0, std::numeric_limits<double>::quiet_NaN()};
  EXPECT_NE(ValidateEnergyBound(b), std::string());
  b.view = {1.0, HUGE_VAL};
  EXPECT_NE(ValidateEnergyBound(b), std::string());
}

}  // namespace
}  // namespace clothfit
