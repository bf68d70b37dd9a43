// Importance sampling of the cloth model (models/cloth_sampling.h): the
// sampled directions follow the stated pdf (chi-square goodness of fit over
// equal-area bins of the sphere), every sample lies above the surface, the
// pdf integrates to 1, and the sampler estimates the directional albedo
// with less variance than cosine sampling.
#include "models/cloth_sampling.h"

#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

#include "models/presets.h"
#include "tests/direction_util.h"
#include "tests/sampling_test_util.h"

namespace clothfit {
namespace {

using testing_util::Dir;
using testing_util::Preset;

using testing_util::BinIntegrals;
using testing_util::Pearson;
using testing_util::SphereBin;

std::vector<double> BinProbabilities(const ClothParams& cloth,
                                     const glm::dvec3& wo, int n) {
  return BinIntegrals(
      [&](const glm::dvec3& w) { return ClothWiPdf(cloth, wo, w); }, n);
}

struct Case {
  const char* preset;
  double theta_o_deg, phi_o_deg;
};

const Case kCases[] = {{"polyester_satin_charmeuse", 40, 10},
                       {"polyester_satin_charmeuse", 75, 200},
                       {"linen_plain", 20, 60},
                       {"silk_shot", 60, 135},
                       {"velvet", 50, 300}};

TEST(ClothSampling, PdfIntegratesToOne) {
  for (const Case& c : kCases) {
    const std::vector<double> p =
        BinProbabilities(Preset(c.preset), Dir(c.theta_o_deg, c.phi_o_deg), 8);
    double sum = 0.0;
    for (double x : p) sum += x;
    EXPECT_NEAR(sum, 1.0, 2e-3) << c.preset << " theta_o " << c.theta_o_deg;
  }
}

TEST(ClothSampling, SampledDirectionsFollowThePdfChiSquare) {
  constexpr int kSamples = 200000;
  for (const Case& c : kCases) {
    const ClothParams cloth = Preset(c.preset);
    const glm::dvec3 wo = Dir(c.theta_o_deg, c.phi_o_deg);
    const std::vector<double> p = BinProbabilities(cloth, wo, 8);
    std::vector<double> counts(p.size(), 0.0);
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int i = 0; i < kSamples; ++i) {
      const ClothSample s = SampleClothWi(cloth, wo, u(rng), u(rng));
      ASSERT_NEAR(glm::length(s.wi), 1.0, 1e-12);
      ASSERT_GE(s.wi.z, 0.0) << "below the surface";
      // The sample's pdf is the mixture density at its direction.
      ASSERT_NEAR(s.pdf, ClothWiPdf(cloth, wo, s.wi), 1e-12 * s.pdf);
      counts[SphereBin(s.wi)] += 1.0;
    }
    const testing_util::ChiSquare chi = Pearson(counts, p, kSamples);
    EXPECT_TRUE(chi.Passes())
        << c.preset << " theta_o " << c.theta_o_deg << ": chi2 "
        << chi.statistic << " (critical " << chi.critical << ") with "
        << chi.dof << " dof, " << chi.stray << " where the pdf is ~0";
  }
}

// Mean and variance of a Monte Carlo estimator's samples.
struct Moments {
  double sum = 0.0, squares = 0.0;
  int n = 0;
  void Add(double x) {
    sum += x;
    squares += x * x;
    ++n;
  }
  double Mean() const { return sum / n; }
  double Variance() const { return squares / n - Mean() * Mean(); }
};

// Directional albedo a(wo) = integral of rho(wi, wo) over wi, estimated
// with the sampler and with cosine sampling alone where the threads'
// highlights dominate: both agree, and the sampler's estimates have the
// smaller variance (over the cases together: where rho is smooth, e.g. at
// grazing wo, cosine sampling alone can win).
TEST(ClothSampling, EstimatesAlbedoWithLessVarianceThanCosineSampling) {
  const Case glossy[] = {{"polyester_satin_charmeuse", 10, 0},
                         {"polyester_satin_charmeuse", 30, 45},
                         {"polyester_satin_charmeuse", 60, 0},
                         {"linen_plain", 30, 0},
                         {"linen_plain", 60, 90},
                         {"silk_crepe_de_chine", 10, 45},
                         {"silk_crepe_de_chine", 30, 0}};
  constexpr int kSamples = 50000;
  double var_is = 0.0, var_cos = 0.0;
  for (const Case& c : glossy) {
    const ClothParams cloth = Preset(c.preset);
    const glm::dvec3 wo = Dir(c.theta_o_deg, c.phi_o_deg);
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    Moments is, cos;
    for (int i = 0; i < kSamples; ++i) {
      const ClothSample s = SampleClothWi(cloth, wo, u(rng), u(rng));
      is.Add(s.pdf > 0.0 ? ClothRho(cloth, s.wi, wo).x / s.pdf : 0.0);
      const double u1 = u(rng), u2 = u(rng);
      const double r = std::sqrt(u1), phi = 2.0 * kPi * u2;
      const glm::dvec3 wi(r * std::cos(phi), r * std::sin(phi),
                          std::sqrt(1.0 - u1));
      cos.Add(ClothRho(cloth, wi, wo).x / (wi.z / kPi));
    }
    const double se = std::sqrt((is.Variance() + cos.Variance()) / kSamples);
    EXPECT_NEAR(is.Mean(), cos.Mean(), 5.0 * se)
        << c.preset << " theta_o " << c.theta_o_deg;
    var_is += is.Variance();
    var_cos += cos.Variance();
  }
  EXPECT_LT(var_is, 0.5 * var_cos)
      << "variance " << var_is << " vs " << var_cos;
}

TEST(ClothSampling, WithoutCoverageOnlyTheCosineHemisphere) {
  ClothParams gaps = Preset("linen_plain");
  for (ClothThread& th : gaps.threads) th.coverage = 0.0;
  const ClothSample s = SampleClothWi(gaps, Dir(30, 0), 0.25, 0.5);
  EXPECT_NEAR(s.wi.z, std::sqrt(0.75), 1e-12);
  EXPECT_NEAR(s.pdf, s.wi.z / kPi, 1e-12);
  EXPECT_EQ(ClothWiPdf(gaps, Dir(30, 0), -Dir(30, 0)), 0.0);
}

}  // namespace
}  // namespace clothfit
