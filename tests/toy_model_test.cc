// A model added the way docs/architecture.md says, in a test: a toy
// model (Minnaert's BRDF) defined by a header's worth of code - its
// parameter table, its struct and visitor, what it evaluates - and a fit
// of a few lines. The library's generic parts (flat vectors, validation,
// the f <-> rho conversion, specs, the one residual, the solver, the
// report) then work for it unchanged.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "data_synthetic/synthetic_table.h"
#include "fitting/least_squares.h"
#include "fitting/model_residual_internal.h"
#include "models/evaluate.h"
#include "models/params.h"

namespace clothfit {

// ---- Step 1: the header (models/minnaert.h) -------------------------------
// Minnaert's BRDF (M. Minnaert, "The reciprocity principle in lunar
// photometry", 1941, eq. 1 written as a BRDF):
//   f = albedo / pi (cos theta_i cos theta_o)^(k - 1),
// Lambertian at k = 1, darker towards the limb for k > 1.
inline constexpr ParamInfo kMinnaertAlbedo = {
    "albedo",
    "unitless",
    "reflectance at normal incidence per channel",
    {0.0, 1.0},
    0.0,
    1.0,
    true,
    {0.5, 0.5, 0.5},
    "Minnaert 1941, eq. 1",
    3};
inline constexpr ParamInfo kMinnaertK = {
    "k",
    "unitless",
    "limb-darkening exponent (1: Lambertian)",
    {0.0, 2.0, true, false},
    0.05,
    2.0,
    false,
    {1.0},
    "Minnaert 1941, eq. 1",
    1};

template <typename T>
struct MinnaertParamsT {
  Vec3<T> albedo = kMinnaertAlbedo.DefaultRgb<T>();
  T k = kMinnaertK.Default<T>();
};
using MinnaertParams = MinnaertParamsT<double>;

template <typename T, typename F>
void VisitParams(MinnaertParamsT<T>& p, F&& f) {
  f(kMinnaertAlbedo, p.albedo);
  f(kMinnaertK, p.k);
}

template <typename T>
inline constexpr ModelInfo kModelInfo<MinnaertParamsT<T>> = {
    "minnaert", Quantity::kBrdf, false};

// The BRDF f (1/sr), reflection only.
template <typename T, typename G>
Vec3<T> NativeValue(const MinnaertParamsT<T>& p, const Vec3<G>& wi,
                    const Vec3<G>& wo) {
  using std::pow;
  if (!(wi.z > G(0.0) && wo.z > G(0.0))) return Vec3<T>(T(0.0));
  return p.albedo * (T(1.0 / kPi) * pow(T(wi.z * wo.z), p.k - T(1.0)));
}

// ---- Step 3: the fit (fitting/minnaert_fit.cc) ----------------------------
namespace {

// The model's value at row i from the one block (the table's order).
struct MinnaertEvaluator {
  const MeasurementTable* table;

  template <typename T>
  Vec3<T> operator()(const T* const* blocks, size_t i) const {
    MinnaertParamsT<T> p;
    FromArray(blocks[0], &p);
    const TableRow& row = table->rows[i];
    return Value(p, row.wi, row.wo, table->quantity);
  }
};

FitResult<MinnaertParams> FitMinnaert(const MeasurementTable& table,
                                      const MinnaertParams& start) {
  LeastSquaresProblem lsq;
  lsq.specs = ParameterSpecs(MinnaertParams());
  lsq.block_sizes = {FlatSize(start)};
  const Weighting weighting(table, NoiseModel());
  lsq.sigma_known = weighting.LevelKnown();
  ResidualBlocks blocks;
  blocks.used = {0};
  SetModelResiduals(
      std::make_shared<const MinnaertEvaluator>(MinnaertEvaluator{&table}),
      TableFitRows(table, weighting), blocks, &lsq);
  std::vector<double> x(FlatSize(start));
  ToArray(start, x.data());
  FitResult<MinnaertParams> result;
  result.report = SolveLeastSquares(lsq, {x}, SolverOptions(), &x);
  FromArray(x.data(), &result.params);
  return result;
}

// ---- Step 5: tests --------------------------------------------------------

MinnaertParams Truth() {
  MinnaertParams p;
  p.albedo = glm::dvec3(0.6, 0.4, 0.2);
  p.k = 1.3;
  return p;
}

TEST(ToyModel, TheGenericPartsReadItsTable) {
  const MinnaertParams p = Truth();
  EXPECT_EQ(FlatSize(p), 4);
  EXPECT_EQ(FlatNames(p), (std::vector<std::string>{"albedo_r", "albedo_g",
                                                    "albedo_b", "k"}));
  double x[4];
  ToArray(p, x);
  EXPECT_EQ(x[2], 0.2);
  EXPECT_EQ(x[3], 1.3);
  MinnaertParams back;
  FromArray(x, &back);
  EXPECT_EQ(back.albedo, p.albedo);
  EXPECT_EQ(back.k, p.k);
  // Defaults from the table.
  EXPECT_EQ(MinnaertParams().k, 1.0);
  EXPECT_EQ(MinnaertParams().albedo, glm::dvec3(0.5));
  // Validation names the entry and its range.
  EXPECT_EQ(ValidateParams(p), "");
  MinnaertParams bad = p;
  bad.k = 0.0;
  EXPECT_EQ(ValidateParams(bad), "k: must be in (0, 2], got 0");
  bad = p;
  bad.albedo.y = 1.5;
  EXPECT_EQ(ValidateParams(bad),
            "albedo: component 1 must be in [0, 1], got 1.5");
  // The fit's specs: the table's bounds and which are physical.
  const std::vector<ParameterSpec> specs = ParameterSpecs(p, "toy.");
  ASSERT_EQ(specs.size(), 4u);
  EXPECT_EQ(specs[3].name, "toy.k");
  EXPECT_EQ(specs[3].lower, 0.05);
  EXPECT_FALSE(specs[3].physical_bounds);
  EXPECT_TRUE(specs[0].physical_bounds);
}

TEST(ToyModel, ValueConvertsItsBrdfToEveryQuantity) {
  const MinnaertParams p = Truth();
  const glm::dvec3 wi = glm::normalize(glm::dvec3(0.3, 0.1, 0.8));
  const glm::dvec3 wo = glm::normalize(glm::dvec3(-0.5, 0.2, 0.6));
  // By hand: albedo / pi (cos_i cos_o)^(k - 1).
  const double shape = std::pow(wi.z * wo.z, 0.3) / kPi;
  const glm::dvec3 f = Value(p, wi, wo, Quantity::kBrdf);
  const glm::dvec3 rho = Value(p, wi, wo, Quantity::kCosineWeighted);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(f[c], p.albedo[c] * shape, 1e-15);
    EXPECT_NEAR(rho[c], p.albedo[c] * shape * wi.z, 1e-15);
  }
  EXPECT_EQ(Rho(p, wi, wo), rho);
  EXPECT_EQ(Brdf(p, wi, wo), f);
  // It predicts no transmittance: zero, not a guess.
  EXPECT_EQ(Value(p, wi, wo, Quantity::kTransmittance), glm::dvec3(0.0));
  EXPECT_FALSE(Predicts<MinnaertParams>(Quantity::kTransmittance));
}

// A table of 400 random direction pairs with 1 % noise and its sigma: the
// fit recovers the truth within 3 of its standard deviations, and those
// are honest (of the order of the noise over sqrt(rows)).
TEST(ToyModel, FitRecoversTheTruthWithHonestStandardDeviations) {
  const MinnaertParams truth = Truth();
  Random random(17);
  DirectionSampling sampling;
  sampling.rows = 400;
  sampling.min_cos_theta = 0.2;  // Minnaert's power is steep at grazing
  MeasurementTable table;
  table.rows = SampleDirections(sampling, &random);
  for (TableRow& row : table.rows) {
    row.value = Value(truth, row.wi, row.wo, Quantity::kBrdf);
  }
  AddMultiplicativeNoise(0.01, glm::dvec3(0.0), &random, &table);
  MinnaertParams start;  // the table's defaults
  const FitResult<MinnaertParams> fit = FitMinnaert(table, start);
  ASSERT_TRUE(fit.report.usable) << fit.report.message;
  EXPECT_TRUE(fit.report.converged) << fit.report.message;
  ASSERT_EQ(fit.report.parameters.size(), 4u);
  const double want[4] = {0.6, 0.4, 0.2, 1.3};
  for (int i = 0; i < 4; ++i) {
    const ParameterReport& p = fit.report.parameters[i];
    ASSERT_GT(p.stddev, 0.0) << p.name;
    EXPECT_LT(p.stddev, 0.01 * std::abs(want[i])) << p.name;
    EXPECT_LT(std::abs(p.value - want[i]), 3.0 * p.stddev) << p.name;
  }
  // chi^2 per degree of freedom near 1: the noise is what is left.
  const double dof = fit.report.residuals - 4.0;
  EXPECT_NEAR(2.0 * fit.report.final_cost / dof, 1.0, 0.2);
  EXPECT_NE(FitReportJson(fit.report).find("\"k\""), std::string::npos);
}

}  // namespace
}  // namespace clothfit
