// The renderer API's prepared evaluation (models/prepared.h) against the
// models themselves: in double the same values to round-off, in float
// within 1e-5 of double, everywhere on the hemisphere including grazing
// directions; a float material beyond float's range stays finite.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "api/material.h"
#include "models/cloth_sampling.h"
#include "models/prepared.h"
#include "models/presets.h"
#include "tests/direction_util.h"

namespace clothfit {
namespace {

using testing_util::Dir;

// Pairs over the hemisphere: thetas up to 89.9 degrees, azimuths all
// round, so that every masking and lobe branch of the cloth is taken.
std::vector<std::pair<glm::dvec3, glm::dvec3>> HemispherePairs() {
  std::vector<std::pair<glm::dvec3, glm::dvec3>> out;
  const double thetas[] = {0.0, 10.0, 35.0, 60.0, 80.0, 89.0, 89.9};
  for (double ti : thetas) {
    for (double to : thetas) {
      for (double pi = 0.0; pi < 360.0; pi += 45.0) {
        for (double po = 7.0; po < 360.0; po += 60.0) {
          out.push_back({Dir(ti, pi), Dir(to, po)});
        }
      }
    }
  }
  return out;
}

// Every preset, a thread, a Lafortune texel with a tilted normal, two lobes
// and a lookup table, one with grey lobes in the surface frame, a rotated
// cloth with a diffuse term, and a slab.
std::vector<std::pair<std::string, ModelParams>> Models() {
  std::vector<std::pair<std::string, ModelParams>> out;
  for (const std::string& name : PresetNames()) {
    ClothParams c;
    EXPECT_TRUE(GetPreset(name, &c));
    out.push_back({name, c});
  }
  ClothParams turned;
  EXPECT_TRUE(GetPreset("linen_plain", &turned));
  turned.rotation_deg = 27.0;
  turned.diffuse = {0.1, 0.05, 0.02};
  turned.threads[0].offsets_deg = {0.0, 35.0};
  out.push_back({"turned linen", turned});
  ThreadParams thread;
  thread.albedo = {0.3, 0.5, 0.7};
  out.push_back({"thread", thread});
  LafortuneModel laf;
  laf.params.lobes = {LafortuneLobe(), LafortuneLobe()};
  laf.params.lobes[0].cx = glm::dvec3(-0.9, -0.8, -0.7);
  laf.params.lobes[1].n = glm::dvec3(3.0, 4.0, 5.0);
  laf.normal = glm::normalize(glm::dvec3(0.2, -0.1, 1.0));
  laf.lut.views = {Dir(20, 0), Dir(60, 90), Dir(40, 200)};
  laf.lut.color = {glm::dvec3(1.2), glm::dvec3(0.8, 0.9, 1.0), glm::dvec3(1.0)};
  laf.lut.alpha = {1.0, 1.0, 1.0};
  out.push_back({"lafortune", laf});
  // Grey lobes in the surface frame: the prepared texel's one power per
  // lobe and no frame rotation (LafortuneShape).
  LafortuneModel grey;
  grey.params.lobes = {LafortuneLobe(), LafortuneLobe()};
  grey.params.lobes[1].n = glm::dvec3(3.0);
  grey.params.lobes[1].cz = glm::dvec3(0.7);
  out.push_back({"grey lafortune", grey});
  SlabParams slab;
  slab.tau = glm::dvec3(0.4);
  slab.albedo = {0.9, 0.8, 0.7};
  out.push_back({"slab", slab});
  return out;
}

double Largest(const glm::dvec3& v) {
  return std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
}

TEST(MaterialPrecision, DoubleEqualsTheModelToRoundOff) {
  for (const auto& [name, params] : Models()) {
    const Material m = Material::FromParams(params);
    double worst = 0.0;
    for (const auto& [wi, wo] : HemispherePairs()) {
      const glm::dvec3 want = Evaluate(params, wi, wo, Quantity::kBrdf);
      const glm::dvec3 got = m.F(wi, wo);
      for (int c = 0; c < 3; ++c) {
        worst = std::max(worst, std::abs(got[c] - want[c]) /
                                    std::max(Largest(want), 1e-300));
      }
    }
    EXPECT_LE(worst, 1e-12) << name;
  }
}

// A prepared cloth evaluates a thread's samples at the same offset once,
// with their count (the satin's warp repeats -32, 0 and 32 degrees; its
// weft is two samples at 0): the values are checked above, the sampling
// density here, against the frames made sample by sample.
TEST(MaterialPrecision, PreparedClothMergesSamplesAtTheSameOffset) {
  ClothParams satin;
  ASSERT_TRUE(GetPreset("polyester_satin_charmeuse", &satin));
  const PreparedCloth<double> p = PrepareCloth<double>(satin);
  ASSERT_EQ(p.frames.size(), 2u);
  std::vector<int> repeats;
  for (const TangentFrame<double>& f : p.frames[0])
    repeats.push_back(f.repeats);
  EXPECT_EQ(repeats, (std::vector<int>{2, 1, 2, 1, 2}));
  EXPECT_EQ(p.Total(0), 8);
  ASSERT_EQ(p.frames[1].size(), 1u);
  EXPECT_EQ(p.frames[1][0].repeats, 2);
  EXPECT_EQ(p.Total(1), 2);
  const ClothFramesOnTheFly<double> each{satin};
  double worst = 0.0;
  for (const auto& [wi, wo] : HemispherePairs()) {
    const double want = ClothWiPdfWithFrames(satin, each, wo, wi);
    const double got = ClothWiPdfWithFrames(satin, p, wo, wi);
    ASSERT_GT(want, 0.0);
    worst = std::max(worst, std::abs(got - want) / want);
  }
  EXPECT_LE(worst, 1e-12);
}

// Float's own rounding shows where a value lies far below the material's
// peak (both directions at 89.9 degrees: f ~ 1e-6 against a peak of 243 for
// the satin): the error is measured against the larger of the value and a
// thousandth of the peak.
TEST(MaterialPrecision, FloatIsWithin1e5OfDouble) {
  const auto pairs = HemispherePairs();
  for (const auto& [name, params] : Models()) {
    const Material md = Material::FromParams(params);
    const MaterialF mf = MaterialF::FromParams(params);
    double peak = 0.0;
    for (const auto& [wi, wo] : pairs)
      peak = std::max(peak, Largest(md.F(wi, wo)));
    ASSERT_GT(peak, 0.0) << name;
    double worst = 0.0;
    for (const auto& [wi, wo] : pairs) {
      const glm::vec3 fwi(wi), fwo(wo);
      const glm::vec3 got = mf.F(fwi, fwo);
      // The double value at the float directions: the figure is the
      // evaluation's own error, not the directions' rounding.
      const glm::dvec3 want = md.F(glm::dvec3(fwi), glm::dvec3(fwo));
      for (int c = 0; c < 3; ++c) {
        ASSERT_TRUE(std::isfinite(got[c])) << name;
        worst = std::max(worst, std::abs(double(got[c]) - want[c]) /
                                    std::max(std::abs(want[c]), 1e-3 * peak));
      }
    }
    EXPECT_LE(worst, 1e-5) << name;
  }
}

// A Lafortune file may hold a lobe peaking at 1e50 (valid: below 1e100);
// float cannot: that texel is evaluated in double and saturated at the
// largest float, and its ordinary values are the double ones rounded.
TEST(MaterialPrecision, FloatLafortuneBeyondFloatRangeStaysFinite) {
  LafortuneModel m;
  m.params.lobes = {LafortuneLobe()};
  m.params.lobes[0].cx = m.params.lobes[0].cy = glm::dvec3(0.0);
  m.params.lobes[0].cz = glm::dvec3(1e20);
  m.params.lobes[0].n = glm::dvec3(2.5);
  const MaterialF mf = MaterialF::FromParams(m);
  const Material md = Material::FromParams(m);
  const glm::vec3 up(0.0f, 0.0f, 1.0f);
  EXPECT_EQ(mf.F(up, up).x, std::numeric_limits<float>::max());
  EXPECT_NEAR(md.F(glm::dvec3(up), glm::dvec3(up)).x, 1e50, 1e38);
  // A light at grazing (l.z = 1e-9): the lobe's value (1e20 * 1e-9)^2.5
  // = 3e27 is a float.
  const glm::vec3 low = glm::normalize(glm::vec3(1.0f, 0.0f, 1e-9f));
  const double want = md.F(glm::dvec3(low), glm::dvec3(up)).x;
  ASSERT_GT(want, 1e20);
  ASSERT_LT(want, 1e38);
  EXPECT_NEAR(mf.F(low, up).x, want, 1e-6 * want);
}

}  // namespace
}  // namespace clothfit
