// The cloth fit's tangent samples with the weave's geometry fixed: held per
// row for a table of at most ClothFitOptions::held_sample_rows rows,
// computed each time a row is evaluated for a larger one. Both give the
// same model values, so the same fit, bit for bit.
#include <gtest/gtest.h>

#include "fitting/cloth_fit.h"
#include "models/presets.h"
#include "tests/fit_test_util.h"

namespace clothfit {
namespace {

// With eta fixed the samples carry their Fresnel terms; with eta free only
// their geometry.
class ClothFitSamples : public ::testing::TestWithParam<bool> {};

TEST_P(ClothFitSamples, ComputedPerRowGiveTheHeldSamplesFit) {
  ClothParams linen;
  ASSERT_TRUE(GetPreset("linen_plain", &linen));
  const MeasurementTable table =
      testing_util::NoisyTable(linen, 0.01, 20261206, 300);
  ClothFitOptions held = testing_util::PaperModel<ClothFitOptions>();
  held.multi_start = false;  // one solve from the generic start
  if (GetParam()) held.also_free = {"eta"};
  ClothFitOptions computed = held;
  computed.held_sample_rows = 0;
  const ClothFitResult a = FitCloth(table, GenericClothStart(linen), held);
  const ClothFitResult b = FitCloth(table, GenericClothStart(linen), computed);
  ASSERT_TRUE(a.report.usable && b.report.usable);
  EXPECT_GT(a.report.iterations, 3);
  ASSERT_EQ(a.report.parameters.size(), b.report.parameters.size());
  for (size_t i = 0; i < a.report.parameters.size(); ++i) {
    EXPECT_EQ(a.report.parameters[i].value, b.report.parameters[i].value)
        << a.report.parameters[i].name;
  }
  EXPECT_EQ(a.report.final_cost, b.report.final_cost);
  EXPECT_EQ(a.report.iterations, b.report.iterations);
}

INSTANTIATE_TEST_SUITE_P(Eta, ClothFitSamples, ::testing::Values(false, true),
                         [](const auto& info) {
                           return std::string(info.param ? "Free" : "Fixed");
                         });

}  // namespace
}  // namespace clothfit
