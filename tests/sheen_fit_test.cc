// The glTF cloth material (models/sheen.h) and its fit
// (fitting/sheen_fit.h): the BRDF's limits, recovery of known parameters
// from noisy tables (within 3 reported sigmas and close to the truth, held
// out rows at the noise level), and the parameter file round trip.
#include "fitting/sheen_fit.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "io/params_json.h"
#include "models/evaluate.h"
#include "tests/direction_util.h"
#include "tests/fit_test_util.h"
#include "tests/io_test_util.h"

namespace clothfit {
namespace {

using testing_util::Dir;
using testing_util::NoisyTable;
using testing_util::Param;
using testing_util::Velvety;

// Without sheen the material is the glTF dielectric: at normal incidence
// (h = n, v.h = 1) F = 0.04, and for roughness 1 (alpha 1) D = 1 / pi and
// V = 1 / 4, so f = 0.96 base_color / pi + 0.04 / (4 pi).
TEST(SheenModel, WithoutSheenItIsTheGltfDielectric) {
  SheenParams p;
  p.sheen_color = glm::dvec3(0.0);
  p.roughness = 1.0;
  p.base_color = glm::dvec3(0.5, 0.25, 1.0);
  const glm::dvec3 n(0.0, 0.0, 1.0);
  const glm::dvec3 f = SheenBrdf(p, n, n);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(f[c], 0.96 * p.base_color[c] / kPi + 0.04 / kPi / 4.0, 1e-15);
  }
  // Below the surface: 0.
  EXPECT_EQ(SheenBrdf(p, -n, n), glm::dvec3(0.0));
  // The sheen alone at grazing retro-reflection is finite and positive.
  SheenParams s = Velvety();
  const glm::dvec3 g = SheenBrdf(s, Dir(89.99, 0), Dir(89.99, 0));
  for (int c = 0; c < 3; ++c) EXPECT_TRUE(std::isfinite(g[c]) && g[c] > 0.0);
}

TEST(SheenFit, RecoversTheParametersWithinThreeSigma) {
  const SheenParams truth = Velvety();
  const MeasurementTable train = NoisyTable(truth, 0.01, 7, 1500);
  const MeasurementTable held_out = NoisyTable(truth, 0.01, 8, 500);
  const SheenFitResult fit = FitSheen(train, SheenFitOptions());
  ASSERT_TRUE(fit.report.converged) << fit.report.message;
  std::vector<double> t(FlatSize(truth));
  ToArray(truth, t.data());
  const std::vector<std::string> names = FlatNames(truth);
  for (size_t k = 0; k < names.size(); ++k) {
    const ParameterReport& r = Param(fit.report, names[k]);
    ASSERT_GT(r.stddev, 0.0) << names[k];
    EXPECT_LT(std::abs(r.value - t[k]), 3.0 * r.stddev) << names[k];
    EXPECT_NEAR(r.value, t[k], 0.01) << names[k];
  }
  // Held-out rows: the relative error is the noise's 1 %.
  double sum = 0.0;
  for (const TableRow& row : held_out.rows) {
    const glm::dvec3 m = Value(fit.params, row.wi, row.wo, held_out.quantity);
    for (int c = 0; c < 3; ++c) sum += Sqr(m[c] / row.value[c] - 1.0);
  }
  EXPECT_LT(std::sqrt(sum / (3.0 * held_out.rows.size())), 0.0105);
}

TEST(SheenFit, FileRoundTripAndErrorsNameTheKey) {
  const SheenParams p = Velvety();
  const ParamFile back =
      ParseParamFile(FormatParamFile(ParamFile(p)), "s.json");
  const SheenParams& q = std::get<SheenParams>(back.params);
  EXPECT_EQ(q.base_color, p.base_color);
  EXPECT_EQ(q.roughness, p.roughness);
  EXPECT_EQ(q.sheen_color, p.sheen_color);
  EXPECT_EQ(q.sheen_roughness, p.sheen_roughness);
  testing_util::ExpectHas(
      testing_util::ErrorOf([] {
        ParseParamFile(
            "{\"model\": \"sheen\", \"base_color\": 0.5, \"roughness\": 0.5, "
            "\"sheen_color\": 1.5, \"sheen_roughness\": 0.5}",
            "s.json");
      }),
      {"s.json", "sheen_color"});
}

}  // namespace
}  // namespace clothfit
