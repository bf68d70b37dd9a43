// Monte Carlo ground truth for the slab (data_synthetic/slab_monte_carlo.h):
// its single-scattering mode against docs/models.md's formulas, energy
// conservation, its two estimators against each other, determinism, and
// the tables it writes.
#include "data_synthetic/slab_monte_carlo.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "io/input_error.h"
#include "models/evaluate.h"
#include "tests/io_test_util.h"

namespace clothfit {
namespace {

SlabMonteCarloOptions Options(const glm::dvec3& tau, const glm::dvec3& albedo,
                              int max_order) {
  SlabMonteCarloOptions o;
  o.params.tau = tau;
  o.params.albedo = albedo;
  o.theta_i_deg = {0.0, 40.0, 70.0};
  o.theta_o_deg = {0.0, 20.0, 45.0, 65.0, 85.0};
  o.photons = 20000;
  o.max_order = max_order;
  o.threads = 2;
  return o;
}

// z-scores (estimate - expected) / standard error over every row and
// channel, each within 5. (The rows of a beam share its photons, so their
// errors are strongly correlated; a mean-square test would not be.)
void ExpectWithinErrorBars(const std::vector<double>& z,
                           const std::string& what) {
  for (double v : z) EXPECT_LT(std::abs(v), 5.0) << what;
}

// Single scattering only: the estimates match the closed forms within
// their own error bars, for shared and per-channel tau.
TEST(SlabMonteCarlo, SingleScatterModeMatchesFormulas) {
  for (const glm::dvec3& tau : {glm::dvec3(0.3), glm::dvec3(0.05, 0.3, 1.5)}) {
    const SlabMonteCarloOptions o = Options(tau, {0.9, 0.5, 0.2}, 1);
    const SlabMonteCarloResult r = RunSlabMonteCarlo(o);
    const MeasurementTable table = SlabMonteCarloBsdfTable(r, Quantity::kBrdf);
    ASSERT_EQ(table.rows.size(), 3u * 2u * 5u);
    std::vector<double> z;
    for (const TableRow& row : table.rows) {
      const glm::dvec3 f = Value(o.params, row.wi, row.wo, Quantity::kBrdf);
      for (int c = 0; c < 3; ++c) {
        EXPECT_GT(row.sigma[c], 0.0);
        EXPECT_LT(row.sigma[c], 0.1 * f[c]);  // meaningful error bars
        z.push_back((row.value[c] - f[c]) / row.sigma[c]);
      }
    }
    ExpectWithinErrorBars(z, "tau " + std::to_string(tau.y));
  }
}

// Direct transmittance: the analog estimate within its error of exp(-tau/mu).
TEST(SlabMonteCarlo, DirectTransmittanceWithinErrorBars) {
  const SlabMonteCarloOptions o = Options({0.2, 0.5, 1.0}, glm::dvec3(0.7), 0);
  const SlabMonteCarloResult r = RunSlabMonteCarlo(o);
  std::vector<double> z;
  for (const SlabMonteCarloBeam& beam : r.beams) {
    const double mu = std::cos(Radians(beam.theta_i_deg));
    for (int c = 0; c < 3; ++c) {
      z.push_back((beam.direct.mean[c] - std::exp(-o.params.tau[c] / mu)) /
                  beam.direct.std_error[c]);
    }
  }
  for (double v : z) EXPECT_LT(std::abs(v), 5.0);
}

// A = 1: all light is reflected, diffusely transmitted or passes straight.
TEST(SlabMonteCarlo, ConservesEnergyWithoutAbsorption) {
  const SlabMonteCarloOptions o = Options(glm::dvec3(0.8), glm::dvec3(1.0), 0);
  const SlabMonteCarloResult r = RunSlabMonteCarlo(o);
  for (const SlabMonteCarloBeam& beam : r.beams) {
    const double total =
        beam.reflected.mean.x + beam.transmitted.mean.x + beam.direct.mean.x;
    const double error = std::sqrt(Sqr(beam.reflected.std_error.x) +
                                   Sqr(beam.transmitted.std_error.x) +
                                   Sqr(beam.direct.std_error.x));
    EXPECT_LT(std::abs(total - 1.0), 5.0 * error + 1e-12)
        << "theta_i " << beam.theta_i_deg << ": " << total;
    // The histogram splits the same energy.
    double hist = 0.0;
    for (const McEstimate& e : beam.reflected_histogram) hist += e.mean.x;
    EXPECT_NEAR(hist, beam.reflected.mean.x, 1e-12);
  }
}

// With every order: the next-event estimates of f_r, f_t integrated over
// the views (Gauss-Legendre in mu) give the escaped energy that the
// escape tally counts independently.
TEST(SlabMonteCarlo, NextEventEstimatesIntegrateToEscapedEnergy) {
  // 8-point Gauss-Legendre nodes and weights on [-1, 1].
  const double x[4] = {0.1834346424956498, 0.5255324099163290,
                       0.7966664774136267, 0.9602898564975363};
  const double w[4] = {0.3626837833783620, 0.3137066458778873,
                       0.2223810344533745, 0.1012285362903763};
  SlabMonteCarloOptions o = Options({0.1, 1.0, 1.0}, {0.95, 0.95, 0.5}, 0);
  o.theta_o_deg.clear();
  std::vector<double> weight;
  for (int k = 0; k < 4; ++k) {
    for (double s : {-1.0, 1.0}) {
      const double mu = 0.5 * (1.0 + s * x[k]);
      o.theta_o_deg.push_back(Degrees(std::acos(mu)));
      // int_0^1 f mu dmu * 2 pi, with dmu = dx / 2.
      weight.push_back(2.0 * kPi * 0.5 * w[k] * mu);
    }
  }
  const SlabMonteCarloResult r = RunSlabMonteCarlo(o);
  for (const SlabMonteCarloBeam& beam : r.beams) {
    glm::dvec3 reflected(0.0), transmitted(0.0);
    for (size_t j = 0; j < weight.size(); ++j) {
      reflected += weight[j] * beam.reflection[j].mean;
      transmitted += weight[j] * beam.transmission[j].mean;
    }
    for (int c = 0; c < 3; ++c) {
      const std::string where = "theta_i " + std::to_string(beam.theta_i_deg) +
                                " channel " + std::to_string(c);
      // Quadrature error ~1e-3 relative near grazing plus 5 sigma.
      EXPECT_NEAR(
          reflected[c], beam.reflected.mean[c],
          5.0 * beam.reflected.std_error[c] + 3e-3 * beam.reflected.mean[c])
          << where;
      EXPECT_NEAR(
          transmitted[c], beam.transmitted.mean[c],
          5.0 * beam.transmitted.std_error[c] + 3e-3 * beam.transmitted.mean[c])
          << where;
    }
  }
}

// Multiple scattering makes the slab brighter than single scattering, by
// about the fraction A q(tau) that models/slab.h estimates.
TEST(SlabMonteCarlo, MultipleScatteringAddsTheEstimatedFraction) {
  const SlabMonteCarloOptions o = Options(glm::dvec3(0.05), {0.9, 0.5, 0.2}, 0);
  const SlabMonteCarloResult r = RunSlabMonteCarlo(o);
  const MeasurementTable table = SlabMonteCarloBsdfTable(r, Quantity::kBrdf);
  for (int c = 0; c < 3; ++c) {
    double se = 0.0, ss = 0.0;
    for (const TableRow& row : table.rows) {
      const double f = Value(o.params, row.wi, row.wo, Quantity::kBrdf)[c];
      EXPECT_GT(row.value[c], f);
      se += Sqr(f - row.value[c]);
      ss += Sqr(row.value[c]);
    }
    EXPECT_NEAR(std::sqrt(se / ss),
                SlabSingleScatterError(0.05, o.params.albedo[c]), 0.01)
        << "channel " << c;
  }
}

TEST(SlabMonteCarlo, DeterministicForAnyThreadCount) {
  SlabMonteCarloOptions o = Options({0.1, 0.1, 0.4}, {0.9, 0.5, 0.7}, 0);
  o.photons = 9000;  // three chunks, the last one partial
  o.threads = 1;
  const MeasurementTable a =
      SlabMonteCarloBsdfTable(RunSlabMonteCarlo(o), Quantity::kBrdf);
  o.threads = 3;
  const MeasurementTable b =
      SlabMonteCarloBsdfTable(RunSlabMonteCarlo(o), Quantity::kBrdf);
  o.seed = 2;
  const MeasurementTable c =
      SlabMonteCarloBsdfTable(RunSlabMonteCarlo(o), Quantity::kBrdf);
  ASSERT_EQ(a.rows.size(), b.rows.size());
  int differ = 0;
  for (size_t i = 0; i < a.rows.size(); ++i) {
    EXPECT_EQ(a.rows[i].value, b.rows[i].value) << i;
    EXPECT_EQ(a.rows[i].sigma, b.rows[i].sigma) << i;
    differ += a.rows[i].value != c.rows[i].value;
  }
  EXPECT_EQ(differ, static_cast<int>(a.rows.size()));
}

TEST(SlabMonteCarlo, TablesFollowSpecLayout) {
  const SlabMonteCarloOptions o = Options(glm::dvec3(0.2), {0.9, 0.5, 0.2}, 0);
  const SlabMonteCarloResult r = RunSlabMonteCarlo(o);
  const MeasurementTable bsdf =
      SlabMonteCarloBsdfTable(r, Quantity::kCosineWeighted);
  const MeasurementTable brdf = SlabMonteCarloBsdfTable(r, Quantity::kBrdf);
  // Per beam: reflection rows (wo.z > 0), then transmission rows.
  size_t i = 0;
  for (double theta_i : o.theta_i_deg) {
    for (int side = 0; side < 2; ++side) {
      for (double theta_o : o.theta_o_deg) {
        const TableRow& row = bsdf.rows[i];
        EXPECT_NEAR(row.wi.z, std::cos(Radians(theta_i)), 1e-15);
        EXPECT_NEAR(std::abs(row.wo.z), std::cos(Radians(theta_o)), 1e-15);
        EXPECT_EQ(row.wo.z < 0.0, side == 1) << i;
        for (int c = 0; c < 3; ++c) {
          EXPECT_NEAR(row.value[c], brdf.rows[i].value[c] * row.wi.z, 1e-18);
        }
        ++i;
      }
    }
  }
  ASSERT_EQ(i, bsdf.rows.size());
  EXPECT_EQ(bsdf.quantity, Quantity::kCosineWeighted);
  EXPECT_TRUE(bsdf.has_sigma);
  EXPECT_EQ(bsdf.Meta("model").value_or(""), "slab");
  EXPECT_TRUE(bsdf.Meta("energy_theta_i_40").has_value());

  const MeasurementTable direct = SlabMonteCarloTransmittanceTable(r);
  const std::string text = FormatTable(direct);
  EXPECT_NE(text.find("# quantity: transmittance\n"), std::string::npos);
  EXPECT_NE(text.find("\ntheta_o,phi_o,value,sigma\n"), std::string::npos)
      << text;
  const MeasurementTable back = ParseTable(text, "D.csv").table;
  ASSERT_EQ(back.rows.size(), o.theta_i_deg.size());
  for (size_t b = 0; b < back.rows.size(); ++b) {
    EXPECT_LT(back.rows[b].wo.z, 0.0);
    EXPECT_NEAR(back.rows[b].value.x, r.beams[b].direct.mean.x, 1e-15);
  }
}

TEST(SlabMonteCarlo, BadOptionsAreRejectedByName) {
  using testing_util::ErrorOf;
  using testing_util::ExpectHas;
  SlabMonteCarloOptions o = Options(glm::dvec3(0.2), glm::dvec3(0.5), 0);
  o.photons = 10;
  EXPECT_EQ(ErrorOf([&] { RunSlabMonteCarlo(o); }), "");
  SlabMonteCarloOptions bad = o;
  bad.theta_o_deg = {10.0, 90.0};
  ExpectHas(ErrorOf([&] { RunSlabMonteCarlo(bad); }), {"theta_o_deg", "90"});
  bad = o;
  bad.theta_i_deg = {};
  ExpectHas(ErrorOf([&] { RunSlabMonteCarlo(bad); }), {"theta_i_deg"});
  bad = o;
  bad.photons = 0;
  ExpectHas(ErrorOf([&] { RunSlabMonteCarlo(bad); }), {"photons"});
  bad = o;
  bad.params.tau = glm::dvec3(0.0);
  ExpectHas(ErrorOf([&] { RunSlabMonteCarlo(bad); }),
            {"tau", "[1e-12, 10000]"});
  bad = o;
  bad.params.albedo = glm::dvec3(1.5);
  ExpectHas(ErrorOf([&] { RunSlabMonteCarlo(bad); }), {"albedo", "1.5"});
}

}  // namespace
}  // namespace clothfit
