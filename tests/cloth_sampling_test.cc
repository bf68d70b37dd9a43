// Importance sampling of the cloth model (models/cloth_sampling.h): the
// sampled directions follow the stated pdf (chi-square goodness of fit over
// equal-area bins of the sphere), the pdf integrates to 1, and the sampler
// estimates the directional albedo with less variance than cosine sampling.
#include "models/cloth_sampling.h"

#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

#include "models/presets.h"

namespace clothfit {
namespace {

ClothParams Preset(const std::string& name) {
  ClothParams c;
  EXPECT_TRUE(GetPreset(name, &c)) << name;
  return c;
}

glm::dvec3 Dir(double theta_deg, double phi_deg) {
  const double t = Radians(theta_deg), p = Radians(phi_deg);
  return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

// Equal-area bins of the sphere: kZ bands in z = cos(theta) times kPhi
// sectors in phi.
constexpr int kZ = 16, kPhi = 32;

int BinOf(const glm::dvec3& w) {
  const int iz = std::min(kZ - 1, static_cast<int>((w.z + 1.0) * 0.5 * kZ));
  double phi = std::atan2(w.y, w.x);
  if (phi < 0.0) phi += 2.0 * kPi;
  const int ip = std::min(kPhi - 1, static_cast<int>(phi / (2.0 * kPi) * kPhi));
  return iz * kPhi + ip;
}

// The pdf integrated over every bin (midpoint rule on an n x n grid in
// (z, phi) per bin; d omega = dz dphi).
std::vector<double> BinProbabilities(const ClothParams& cloth,
                                     const glm::dvec3& wo, int n) {
  std::vector<double> p(kZ * kPhi, 0.0);
  const double dz = 2.0 / (kZ * n), dphi = 2.0 * kPi / (kPhi * n);
  for (int i = 0; i < kZ * n; ++i) {
    const double z = -1.0 + (i + 0.5) * dz;
    const double r = std::sqrt(1.0 - z * z);
    for (int k = 0; k < kPhi * n; ++k) {
      const double phi = (k + 0.5) * dphi;
      const glm::dvec3 w(r * std::cos(phi), r * std::sin(phi), z);
      p[(i / n) * kPhi + k / n] += ClothWiPdf(cloth, wo, w) * dz * dphi;
    }
  }
  return p;
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
      const ClothSample s = SampleClothWi(cloth, wo, u(rng), u(rng), u(rng));
      ASSERT_NEAR(glm::length(s.wi), 1.0, 1e-12);
      // The sample's pdf is the mixture density at its direction.
      ASSERT_NEAR(s.pdf, ClothWiPdf(cloth, wo, s.wi), 1e-12 * s.pdf);
      counts[BinOf(s.wi)] += 1.0;
    }
    // Pearson's statistic, bins with fewer than 5 expected pooled.
    double chi2 = 0.0, pooled_expected = 0.0, pooled_count = 0.0;
    int bins = 0;
    for (size_t b = 0; b < p.size(); ++b) {
      const double expected = p[b] * kSamples;
      if (expected < 5.0) {
        pooled_expected += expected;
        pooled_count += counts[b];
        continue;
      }
      chi2 += (counts[b] - expected) * (counts[b] - expected) / expected;
      ++bins;
    }
    if (pooled_expected >= 5.0) {
      chi2 += (pooled_count - pooled_expected) *
              (pooled_count - pooled_expected) / pooled_expected;
      ++bins;
    } else {
      EXPECT_LT(pooled_count, 20.0) << "samples where the pdf is ~0";
    }
    // Critical value at significance 1e-4 (Wilson-Hilferty).
    const double k = bins - 1;
    const double a = 2.0 / (9.0 * k);
    const double critical = k * std::pow(1.0 - a + 3.719 * std::sqrt(a), 3);
    EXPECT_LT(chi2, critical) << c.preset << " theta_o " << c.theta_o_deg
                              << ": chi2 " << chi2 << " with " << k << " dof";
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
// grazing wo, cosine sampling alone can win by up to 3x).
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
      const ClothSample s = SampleClothWi(cloth, wo, u(rng), u(rng), u(rng));
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
  const ClothSample s = SampleClothWi(gaps, Dir(30, 0), 0.9, 0.25, 0.5);
  EXPECT_NEAR(s.wi.z, std::sqrt(0.75), 1e-12);
  EXPECT_NEAR(s.pdf, s.wi.z / kPi, 1e-12);
  EXPECT_EQ(ClothWiPdf(gaps, Dir(30, 0), -Dir(30, 0)), 0.0);
}

}  // namespace
}  // namespace clothfit
