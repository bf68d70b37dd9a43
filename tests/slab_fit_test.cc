// The slab fit (fitting/slab_fit.h): recovery from model data and from
// Monte Carlo ground truth, the validity report, and unusable input.
#include "fitting/slab_fit.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "data_synthetic/slab_monte_carlo.h"
#include "data_synthetic/synthetic_table.h"
#include "io/input_error.h"
#include "tests/fit_test_util.h"
#include "tests/io_test_util.h"

namespace clothfit {
namespace {

using testing_util::ErrorOf;
using testing_util::ExpectHas;

const std::vector<double> kThetaI = {0.0, 20.0, 40.0, 60.0, 75.0};
const std::vector<double> kThetaO = {0.0, 15.0, 30.0, 45.0, 60.0, 75.0, 85.0};

// The single-scattering model's values at the Monte Carlo's directions: a
// BSDF table (reflection and transmission rows) and a direct-transmittance
// table, with relative noise (and sigma) when noise > 0.
std::vector<MeasurementTable> ModelTables(const SlabParams& truth, double noise,
                                          Quantity quantity, uint64_t seed) {
  Random random(seed);
  SynthOptions synth;
  synth.noise = noise;
  synth.quantity = quantity;
  const SlabTables t = SlabModelTables(truth, kThetaI, kThetaO, synth, &random);
  return {t.bsdf, t.transmittance};
}

std::vector<MeasurementTable> MonteCarloTables(const SlabParams& truth,
                                               int64_t photons) {
  SlabMonteCarloOptions o;
  o.params = truth;
  o.theta_i_deg = kThetaI;
  o.theta_o_deg = kThetaO;
  o.photons = photons;
  o.threads = 2;
  const SlabMonteCarloResult r = RunSlabMonteCarlo(o);
  return {SlabMonteCarloBsdfTable(r, Quantity::kBrdf),
          SlabMonteCarloTransmittanceTable(r)};
}

void ExpectRel(double actual, double expected, double tolerance,
               const std::string& what) {
  EXPECT_LE(std::abs(actual - expected), tolerance * std::abs(expected))
      << what << ": " << actual << " vs " << expected;
}

void ExpectParams(const SlabParams& fit, const SlabParams& truth,
                  double tolerance, const std::string& what) {
  for (int c = 0; c < 3; ++c) {
    ExpectRel(fit.tau[c], truth.tau[c], tolerance,
              what + " tau " + std::to_string(c));
    ExpectRel(fit.albedo[c], truth.albedo[c], tolerance,
              what + " albedo " + std::to_string(c));
  }
}

SlabParams Truth(const glm::dvec3& tau, const glm::dvec3& albedo) {
  SlabParams p;
  p.tau = tau;
  p.albedo = albedo;
  return p;
}

TEST(SlabFit, RecoversNoiseFreeModelData) {
  struct Case {
    SlabParams truth;
    bool per_channel;
    Quantity quantity;
  };
  for (const Case& k :
       {Case{Truth(glm::dvec3(0.08), {0.9, 0.6, 0.3}), false, Quantity::kBrdf},
        Case{Truth({0.02, 0.3, 1.5}, {0.7, 0.95, 0.2}), true,
             Quantity::kCosineWeighted},
        Case{Truth(glm::dvec3(2.5), {0.5, 0.5, 0.5}), false,
             Quantity::kBrdf}}) {
    SlabFitOptions options;
    options.per_channel_tau = k.per_channel;
    const SlabFitResult r =
        FitSlab(ModelTables(k.truth, 0.0, k.quantity, 1), options);
    const std::string what = "tau " + std::to_string(k.truth.tau.x);
    ASSERT_TRUE(r.report.usable) << what << ": " << r.report.message;
    EXPECT_TRUE(r.report.converged) << what << ": " << r.report.message;
    ExpectParams(r.params, k.truth, 1e-6, what);
    EXPECT_EQ(r.report.parameters.size(), k.per_channel ? 6u : 4u);
    EXPECT_EQ(r.report.identifiability, "") << what;
  }
}

// Reflection rows alone (no transmittance table) still determine both.
TEST(SlabFit, RecoversFromReflectionOnly) {
  const SlabParams truth = Truth(glm::dvec3(0.3), glm::dvec3(0.6));
  std::vector<MeasurementTable> tables =
      ModelTables(truth, 0.0, Quantity::kBrdf, 1);
  MeasurementTable& bsdf = tables[0];
  std::vector<TableRow> reflection;
  for (const TableRow& row : bsdf.rows) {
    if (row.wo.z > 0.0) reflection.push_back(row);
  }
  bsdf.rows = reflection;
  const SlabFitResult r = FitSlab({bsdf}, SlabFitOptions());
  ASSERT_TRUE(r.report.converged) << r.report.message;
  ExpectParams(r.params, truth, 1e-6, "reflection only");
}

// Noisy model data: within a few standard deviations, and the validity
// report finds the error at the noise level in the thin regime.
TEST(SlabFit, NoisyDataWithinStandardDeviationsAndWithinRegime) {
  const SlabParams truth = Truth(glm::dvec3(0.004), {0.5, 0.3, 0.1});
  const SlabFitResult r =
      FitSlab(ModelTables(truth, 0.02, Quantity::kBrdf, 7), SlabFitOptions());
  ASSERT_TRUE(r.report.converged) << r.report.message;
  ASSERT_EQ(r.report.parameters.size(), 4u);
  const std::vector<double> want = SlabValuesInReportOrder(truth, r.report);
  for (size_t i = 0; i < want.size(); ++i) {
    const ParameterReport& p = r.report.parameters[i];
    ASSERT_GT(p.stddev, 0.0) << p.name;
    EXPECT_LT(std::abs(p.value - want[i]), 4.0 * p.stddev) << p.name;
  }
  const SlabValidity& v = r.validity;
  EXPECT_TRUE(v.sigma_known);
  EXPECT_FALSE(v.error_exceeds_noise) << v.chi2_per_dof;
  EXPECT_FALSE(v.multiple_scattering) << v.estimated_model_error;
  EXPECT_FALSE(v.above_paper_tau_limit);
  EXPECT_TRUE(v.within_regime);
  EXPECT_GT(v.improvement, 3.0);  // the slab explains it better than alpha
}

// Monte Carlo ground truth at tau = 0.05, all orders of scattering. At a
// low albedo multiple scattering adds ~2-4 %: tau and albedo within 5 %.
TEST(SlabFit, RecoversMonteCarloDataAtTau005) {
  const SlabParams truth = Truth(glm::dvec3(0.05), {0.4, 0.3, 0.2});
  const SlabFitResult r =
      FitSlab(MonteCarloTables(truth, 20000), SlabFitOptions());
  ASSERT_TRUE(r.report.converged) << r.report.message;
  ExpectParams(r.params, truth, 0.05, "Monte Carlo");
  // The albedo corrected for multiple scattering is closer still.
  for (int c = 0; c < 3; ++c) {
    ExpectRel(r.validity.corrected_albedo[c], truth.albedo[c], 0.015,
              "corrected albedo " + std::to_string(c));
  }
}

// At a high albedo the single-scattering fit absorbs ~9 % of multiple
// scattering into the albedo; the report says so and corrects it.
TEST(SlabFit, FlagsMultipleScatteringAtHighAlbedo) {
  const SlabParams truth = Truth(glm::dvec3(0.05), {0.9, 0.9, 0.9});
  const SlabFitResult r =
      FitSlab(MonteCarloTables(truth, 20000), SlabFitOptions());
  ASSERT_TRUE(r.report.converged) << r.report.message;
  ExpectRel(r.params.tau.x, 0.05, 0.02, "tau");
  EXPECT_GT(r.params.albedo.x, 0.9 * 1.05);
  EXPECT_LT(r.params.albedo.x, 0.9 * 1.15);
  const SlabValidity& v = r.validity;
  EXPECT_TRUE(v.multiple_scattering);
  EXPECT_FALSE(v.within_regime);
  EXPECT_FALSE(v.above_paper_tau_limit);  // the paper's bound misses it
  ExpectRel(v.corrected_albedo.x, 0.9, 0.02, "corrected albedo");
}

// A thick, bright slab: the single-scattering form cannot follow the
// Monte Carlo's angular shape, and the error exceeds the noise.
TEST(SlabFit, ModelErrorExceedsNoiseWhenThick) {
  const SlabParams truth = Truth(glm::dvec3(1.0), glm::dvec3(1.0));
  const SlabFitResult r =
      FitSlab(MonteCarloTables(truth, 20000), SlabFitOptions());
  ASSERT_TRUE(r.report.usable) << r.report.message;
  const SlabValidity& v = r.validity;
  EXPECT_TRUE(v.error_exceeds_noise) << v.chi2_per_dof;
  EXPECT_GT(v.chi2_per_dof, 10.0 * v.chi2_limit);
  EXPECT_TRUE(v.above_paper_tau_limit);
  EXPECT_FALSE(v.within_regime);
}

// Data made by the constant-alpha baseline itself: the baseline explains
// them exactly, the slab model does not (improvement < 1).
TEST(SlabFit, BaselineWinsOnItsOwnData) {
  std::vector<MeasurementTable> tables = ModelTables(
      Truth(glm::dvec3(0.1), glm::dvec3(0.5)), 0.0, Quantity::kBrdf, 1);
  for (TableRow& row : tables[0].rows) row.value = glm::dvec3(0.02);
  for (TableRow& row : tables[1].rows) row.value = glm::dvec3(0.8);
  const SlabFitResult r = FitSlab(tables, SlabFitOptions());
  ASSERT_TRUE(r.report.usable);
  EXPECT_LT(r.validity.baseline_rms, 1e-12);
  EXPECT_LT(r.validity.improvement, 1.0);
  EXPECT_NE(r.validity.baseline.find("front-lit"), std::string::npos);
  // The note says which is better, in finite words (it said "0.795x lower"
  // for a worse slab, and "infx lower" when the slab fitted exactly).
  std::string notes;
  for (const std::string& note : r.validity.notes) notes += note + "\n";
  EXPECT_EQ(notes.find("x lower"), std::string::npos) << notes;
  EXPECT_TRUE(notes.find("the baseline fits exactly") != std::string::npos ||
              notes.find("x higher") != std::string::npos)
      << notes;
}

TEST(SlabFit, FixedParametersKeepTheirValue) {
  const SlabParams truth = Truth(glm::dvec3(0.2), {0.8, 0.6, 0.4});
  SlabFitOptions options;
  options.init = Truth(glm::dvec3(0.25), glm::dvec3(0.5));
  options.fix = {"tau"};
  const SlabFitResult r =
      FitSlab(ModelTables(truth, 0.0, Quantity::kBrdf, 1), options);
  ASSERT_TRUE(r.report.usable);
  EXPECT_EQ(r.params.tau, glm::dvec3(0.25));
  EXPECT_FALSE(r.report.parameters[0].free);
}

// A direct-transmittance table alone says nothing about the albedo.
TEST(SlabFit, TransmittanceAloneLeavesAlbedoUndetermined) {
  const SlabParams truth = Truth(glm::dvec3(0.2), glm::dvec3(0.5));
  const std::vector<MeasurementTable> tables =
      ModelTables(truth, 0.0, Quantity::kBrdf, 1);
  const SlabFitResult r = FitSlab({tables[1]}, SlabFitOptions());
  ASSERT_TRUE(r.report.usable);
  ExpectRel(r.params.tau.x, 0.2, 1e-6, "tau");
  const std::vector<std::string> undetermined =
      testing_util::UndeterminedNames(r.report.identifiability);
  EXPECT_TRUE(testing_util::Contains(undetermined, "albedo"))
      << r.report.identifiability;
}

TEST(SlabFit, UnusableInputIsRejected) {
  const SlabParams truth = Truth(glm::dvec3(0.2), glm::dvec3(0.5));
  std::vector<MeasurementTable> tables =
      ModelTables(truth, 0.0, Quantity::kBrdf, 1);
  ExpectHas(ErrorOf([&] { FitSlab({}, SlabFitOptions()); }), {"no tables"});
  MeasurementTable empty = tables[0];
  empty.rows.clear();
  ExpectHas(ErrorOf([&] { FitSlab({empty}, SlabFitOptions()); }), {"no rows"});
  MeasurementTable with_sigma = tables[1];
  with_sigma.has_sigma = true;
  ExpectHas(ErrorOf([&] {
              FitSlab({tables[0], with_sigma}, SlabFitOptions());
            }),
            {"sigma"});
  MeasurementTable one_channel = tables[0];
  one_channel.channels = 1;
  ExpectHas(ErrorOf([&] {
              FitSlab({one_channel, tables[0]}, SlabFitOptions());
            }),
            {"one-channel"});
  SlabFitOptions per_channel;
  per_channel.per_channel_tau = true;
  ExpectHas(ErrorOf([&] { FitSlab(tables, per_channel); }), {"one-channel"});
  SlabFitOptions unknown;
  unknown.fix = {"thickness"};
  ExpectHas(ErrorOf([&] { FitSlab(tables, unknown); }), {"thickness"});
}

}  // namespace
}  // namespace clothfit
