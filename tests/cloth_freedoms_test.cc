// The cloth fit's optional freedoms (fitting/cloth_fit.h,
// models/microcylinder_cloth.h): a weave turned about the normal, tangent
// offsets of its own (a flat sample among them) and a Lambertian term are
// recovered from a noise-free table, from the paper's weave and generic
// thread values, by the space-filling start search; the names free as
// documented; the multi-start's stopping rule is reported.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "fitting/cloth_fit.h"
#include "io/input_error.h"
#include "models/presets.h"
#include "tests/fit_test_util.h"

namespace clothfit {
namespace {

ClothParams Linen() {
  ClothParams c;
  EXPECT_TRUE(GetPreset("linen_plain", &c));
  return c;
}

// linen_plain turned by 25 degrees, its warp with a flat sample and a
// steeper one (0, 35), its weft narrower and redder, unequal coverages, and
// a Lambertian term: no symmetry of the weave left but the one every weave
// has (a half turn with every offset negated).
ClothParams Truth() {
  ClothParams c = Linen();
  c.rotation_deg = 25.0;
  c.diffuse = glm::dvec3(0.04, 0.08, 0.12);
  c.threads[0].coverage = 0.45;
  c.threads[0].offsets_deg = {0.0, 35.0};
  c.threads[0].curve = TangentCurve();
  c.threads[1].coverage = 0.3;
  c.threads[1].params.gamma_s_deg = 20.0;
  c.threads[1].params.albedo = glm::dvec3(0.3, 0.1, 0.05);
  return c;
}

using testing_util::Param;

TEST(ClothFreedoms, RotationOffsetsAndDiffuseAreRecoveredFromTheGenericStart) {
  const ClothParams truth = Truth();
  const MeasurementTable table =
      testing_util::NoisyTable(truth, 0.0, 20260512, 600);
  ClothParams start = GenericClothStart(Linen());
  for (size_t j = 0; j < 2; ++j) {
    start.threads[j].coverage = truth.threads[j].coverage;  // fixed
  }
  ClothFitOptions options = testing_util::PaperModel<ClothFitOptions>();
  options.also_free = {"rotation_deg", "offsets_deg", "diffuse"};
  options.solve_starts = 8;
  const ClothFitResult r = FitCloth(table, start, options);
  ASSERT_TRUE(r.report.usable) << r.report.message;
  EXPECT_LT(r.report.relative_rms, 1e-4);
  EXPECT_NE(r.report.search.find("weave geometries searched"),
            std::string::npos)
      << r.report.search;
  // Up to the half turn: rotation r + 180 with offsets -psi is the same.
  ClothParams fit = r.params;
  if (std::abs(std::remainder(fit.rotation_deg - truth.rotation_deg, 360.0)) >
      90.0) {
    fit.rotation_deg -= 180.0;
    for (ClothThread& th : fit.threads) {
      for (double& o : th.offsets_deg) o = -o;
    }
  }
  EXPECT_NEAR(std::remainder(fit.rotation_deg - truth.rotation_deg, 360.0), 0.0,
              0.05);
  for (size_t j = 0; j < 2; ++j) {
    // A thread's samples are summed: their order is not determined.
    std::vector<double> got = fit.threads[j].offsets_deg;
    std::vector<double> want = truth.threads[j].offsets_deg;
    std::sort(got.begin(), got.end());
    std::sort(want.begin(), want.end());
    for (size_t k = 0; k < want.size(); ++k) {
      EXPECT_NEAR(got[k], want[k], 0.05) << "thread " << j << " sample " << k;
    }
    const ThreadParams& p = fit.threads[j].params;
    const ThreadParams& q = truth.threads[j].params;
    EXPECT_NEAR(p.gamma_s_deg, q.gamma_s_deg, 1e-3 * q.gamma_s_deg) << j;
    EXPECT_NEAR(p.gamma_v_deg, q.gamma_v_deg, 1e-3 * q.gamma_v_deg) << j;
    EXPECT_NEAR(p.kd, q.kd, 1e-3) << j;
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(p.albedo[c], q.albedo[c], 1e-3 * q.albedo[c]) << j;
    }
  }
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(fit.diffuse[c], truth.diffuse[c], 1e-3 * truth.diffuse[c]);
  }
  // The report gives what the file holds (rotation in (-180, 180]).
  EXPECT_EQ(Param(r.report, "rotation_deg").value, r.params.rotation_deg);
  EXPECT_GT(r.params.rotation_deg, -180.0);
  EXPECT_LE(r.params.rotation_deg, 180.0);
  EXPECT_EQ(Param(r.report, "diffuse_b").value, r.params.diffuse.z);
  EXPECT_GT(Param(r.report, "rotation_deg").stddev, 0.0);
  // Moved samples are written as samples, not as the preset's curve.
  EXPECT_EQ(r.params.threads[0].curve.samples, 0);
}

TEST(ClothFreedoms, TheDefaultIsThePapersModel) {
  const ClothParams truth = Linen();
  const MeasurementTable table = testing_util::NoisyTable(truth, 0.0, 7, 200);
  const ClothFitResult r =
      FitCloth(table, GenericClothStart(truth),
               testing_util::PaperModel<ClothFitOptions>());
  for (const char* name :
       {"rotation_deg", "diffuse_r", "threads[0].offsets_deg[0]",
        "threads[1].offsets_deg[1]"}) {
    EXPECT_FALSE(Param(r.report, name).free) << name;
  }
  EXPECT_EQ(r.params.rotation_deg, 0.0);
  EXPECT_EQ(r.params.diffuse, glm::dvec3(0.0));
  EXPECT_EQ(r.report.search, "");  // no design without free geometry
}

TEST(ClothFreedoms, NamesFreeTheirEntriesAndConflictsAreRefused) {
  const ClothParams truth = Linen();
  const MeasurementTable table = testing_util::NoisyTable(truth, 0.0, 7, 200);
  ClothFitOptions options = testing_util::PaperModel<ClothFitOptions>();
  options.also_free = {"threads[1].offsets_deg"};
  options.design_points = 4;
  options.solve_starts = 1;
  const ClothFitResult r = FitCloth(table, GenericClothStart(truth), options);
  EXPECT_FALSE(Param(r.report, "threads[0].offsets_deg[0]").free);
  EXPECT_TRUE(Param(r.report, "threads[1].offsets_deg[0]").free);
  EXPECT_TRUE(Param(r.report, "threads[1].offsets_deg[1]").free);
  EXPECT_TRUE(Param(r.report, "threads[0].kd").free);  // the default set
  EXPECT_EQ(r.report.starts, 1);
  options.also_free = {"offsets_deg", "offset_scale"};
  EXPECT_THROW(FitCloth(table, GenericClothStart(truth), options), InputError);
  options.also_free = {"rotation"};
  try {
    FitCloth(table, GenericClothStart(truth), options);
    ADD_FAILURE() << "an unknown name was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--also-free"), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("'rotation'"), std::string::npos)
        << e.what();
  }
  // --fix wins over --also-free.
  options.also_free = {"diffuse"};
  options.fix = {"diffuse"};
  EXPECT_FALSE(Param(FitCloth(table, GenericClothStart(truth), options).report,
                     "diffuse_r")
                   .free);
  // Fixing the whole default set leaves the freedoms to fit; fixing those
  // too leaves nothing.
  options.fix = {"kd", "gamma_s_deg", "gamma_v_deg", "albedo"};
  options.also_free = {"rotation_deg"};
  const ClothFitResult rotation_only =
      FitCloth(table, GenericClothStart(truth), options);
  EXPECT_TRUE(rotation_only.report.usable) << rotation_only.report.message;
  for (const ParameterReport& p : rotation_only.report.parameters) {
    EXPECT_EQ(p.free, p.name == "rotation_deg") << p.name;
  }
  options.fix.push_back("rotation_deg");
  EXPECT_THROW(FitCloth(table, GenericClothStart(truth), options), InputError);
}

}  // namespace
}  // namespace clothfit
