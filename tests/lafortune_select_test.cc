// Held-out model selection for Lafortune fits (fit --select heldout):
// k-fold over the table's lights, each candidate scored on lights it never
// saw; for texel tables with --mip, the mip level the data support.
#include "fitting/lafortune_select.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "fitting/lafortune_level_select.h"
#include "io/input_error.h"
#include "models/evaluate.h"
#include "tests/cli_test_util.h"
#include "tests/fit_test_util.h"
#include "tests/io_test_util.h"

namespace clothfit {
namespace {

namespace fs = std::filesystem;
using testing_util::Hemisphere;
using testing_util::LafortuneTable;

// A plausible 1-lobe texel with a view-dependent table.
LafortuneModel OneLobeTruth(const std::vector<glm::dvec3>& views) {
  LafortuneModel m;
  m.params.diffuse = {0.08, 0.06, 0.04};
  LafortuneLobe lobe;
  lobe.cx = {-0.95, -0.9, -0.85};
  lobe.cy = {-0.9, -0.95, -0.85};
  lobe.cz = {1.0, 0.95, 0.9};
  lobe.n = {12, 10, 8};
  m.params.lobes = {lobe};
  for (size_t k = 0; k < views.size(); ++k) {
    m.lut.views.push_back(views[k]);
    m.lut.color.push_back(glm::dvec3(0.8 + 0.2 * std::sin(2.0 * k)));
    m.lut.alpha.push_back(1.0);
  }
  return m;
}

// 36 lights x 16 views of the truth with 3 % multiplicative noise (a fixed
// sequence): the candidates without lobes lose on held-out lights, the
// chosen one is close to the truth at lights none of its fits saw, and a
// candidate's held-out error is never below the noise it cannot predict.
TEST(LafortuneSelect, ChoosesAModelThatPredictsUnseenLights) {
  const std::vector<glm::dvec3> views = Hemisphere(4);
  const LafortuneModel truth = OneLobeTruth(views);
  MeasurementTable table = LafortuneTable(truth, Hemisphere(6), views);
  table.source = "synthetic";
  uint64_t state = 12345;
  for (TableRow& r : table.rows) {
    for (int c = 0; c < 3; ++c) {
      state = state * 6364136223846793005ull + 1442695040888963407ull;
      const double u = ((state >> 11) * (1.0 / 9007199254740992.0)) - 0.5;
      r.value[c] *= 1.0 + 0.03 * std::sqrt(12.0) * u;  // sd 3 %
    }
  }
  LafortuneMipOptions options;
  options.mip = false;
  const LafortuneSelection s = SelectLafortuneHeldOut(table, options, 5);
  ASSERT_EQ(s.report.candidates.size(), 8u);  // 0..3 lobes, table off/on
  ASSERT_GE(s.report.chosen, 0);
  const CandidateReport& chosen = s.report.candidates[s.report.chosen];
  EXPECT_GE(s.fit.params.params.lobes.size(), 1u) << chosen.description;
  for (const CandidateReport& c : s.report.candidates) {
    ASSERT_TRUE(c.usable) << c.description;
    EXPECT_GE(c.heldout_relative_rms, 0.025) << c.description;
    EXPECT_GE(c.heldout_relative_rms, chosen.heldout_relative_rms);
    if (c.description.rfind("0 lobe", 0) == 0) {
      EXPECT_GT(c.heldout_relative_rms, 2.0 * chosen.heldout_relative_rms);
    }
  }
  // Against the noise-free truth at lights between the table's.
  double se = 0.0, ss = 0.0;
  for (const glm::dvec3& l : Hemisphere(5, 0.37)) {
    for (const glm::dvec3& v : views) {
      const glm::dvec3 d =
          LafortuneRho(s.fit.params, l, v) - LafortuneRho(truth, l, v);
      const glm::dvec3 y = LafortuneRho(truth, l, v);
      se += glm::dot(d, d);
      ss += glm::dot(y, y);
    }
  }
  EXPECT_LT(std::sqrt(se / ss), 0.03);
}

TEST(LafortuneSelect, FewerLightsThanFoldsIsBadInput) {
  const std::vector<glm::dvec3> views = Hemisphere(3);
  MeasurementTable table =
      LafortuneTable(OneLobeTruth(views), Hemisphere(2), views);  // 4 lights
  table.source = "t.csv";
  EXPECT_THROW(SelectLafortuneHeldOut(table, LafortuneMipOptions(), 5),
               InputError);
}

// A 4 x 4 texel table whose texels are the halves of two materials (a
// dark left and a bright right half, `split`) or all one material, each
// texel's rows with its own 10 % noise: 16 lights x 4 views per texel, too
// few to tell a texel's noise from its material.
MeasurementTable TexelTable(bool split) {
  const std::vector<glm::dvec3> views = Hemisphere(2, 0.25);
  LafortuneModel dark = OneLobeTruth(views);
  dark.params.lobes[0].cx = glm::dvec3(-0.6);  // a broad lobe
  dark.params.lobes[0].cy = glm::dvec3(-0.6);
  dark.params.lobes[0].cz = glm::dvec3(0.7);
  dark.params.lobes[0].n = glm::dvec3(3.0);
  LafortuneModel bright = dark;
  bright.params.diffuse *= 4.0;
  MeasurementTable table;
  table.source = "texels";
  table.quantity = Quantity::kCosineWeighted;  // LafortuneTable's values
  table.channels = 3;
  table.has_texels = true;
  uint64_t state = 777;
  for (int t = 0; t < 4; ++t) {
    for (int s = 0; s < 4; ++s) {
      const LafortuneModel& m = split && s >= 2 ? bright : dark;
      for (TableRow r : LafortuneTable(m, Hemisphere(4, 0.2), views).rows) {
        r.s = s;
        r.t = t;
        for (int c = 0; c < 3; ++c) {
          state = state * 6364136223846793005ull + 1442695040888963407ull;
          const double u = ((state >> 11) * (1.0 / 9007199254740992.0)) - 0.5;
          r.value[c] *= 1.0 + 0.1 * std::sqrt(12.0) * u;
        }
        table.rows.push_back(r);
      }
    }
  }
  return table;
}

TEST(LafortuneLevelSelect, OneMaterialIsFittedAtTheCoarsestLevel) {
  LafortuneMipOptions options;
  options.fit.lobes = 1;
  const LafortuneLevelSelection s =
      SelectLafortuneLevelHeldOut(TexelTable(false), options, 5);
  ASSERT_EQ(s.report.candidates.size(), 3u);  // 4 x 4, 2 x 2, 1 x 1
  for (const CandidateReport& c : s.report.candidates) {
    ASSERT_TRUE(c.usable) << c.description;
    std::printf("%s: training %.4g, held-out %.4g\n", c.description.c_str(),
                c.relative_rms, c.heldout_relative_rms);
  }
  // Level 0 fits each texel's noise: best on its own rows, worst on
  // lights it never saw.
  EXPECT_LT(s.report.candidates[0].relative_rms,
            s.report.candidates[2].relative_rms);
  EXPECT_GT(s.report.candidates[0].heldout_relative_rms,
            s.report.candidates[2].heldout_relative_rms);
  EXPECT_EQ(s.level, 2);
  EXPECT_EQ(s.report.chosen, 2);
  // Every finer texel holds the chosen level's model.
  const LafortuneModel& top = s.mip.levels[2].texels[0].params;
  for (int l = 0; l < 2; ++l) {
    for (const LafortuneFitResult& t : s.mip.levels[l].texels) {
      EXPECT_EQ(t.params.params.diffuse, top.params.diffuse) << l;
      EXPECT_EQ(t.params.params.lobes[0].n, top.params.lobes[0].n) << l;
    }
  }
}

TEST(LafortuneLevelSelect, TwoMaterialsKeepTheLevelThatSeparatesThem) {
  LafortuneMipOptions options;
  options.fit.lobes = 1;
  const LafortuneLevelSelection s =
      SelectLafortuneLevelHeldOut(TexelTable(true), options, 5);
  ASSERT_EQ(s.report.candidates.size(), 3u);
  std::printf("%s", SelectionReportText(s.report).c_str());
  // Level 1's 2 x 2 groups are each one material; the 1 x 1 level mixes.
  EXPECT_EQ(s.level, 1) << SelectionReportText(s.report);
  const std::vector<LafortuneFitResult>& level0 = s.mip.levels[0].texels;
  EXPECT_EQ(level0[0].params.params.diffuse, level0[5].params.params.diffuse);
  // The bright half reflects about 4 times the dark half's diffuse.
  const glm::dvec3 wi = DirectionFromAngles(Radians(30.0), 0.0);
  const glm::dvec3 wo = DirectionFromAngles(Radians(45.0), Radians(120.0));
  const double dark = LafortuneRho(level0[0].params, wi, wo).x;
  const double bright = LafortuneRho(level0[3].params, wi, wo).x;
  std::printf("dark %.4g, bright %.4g\n", dark, bright);
  EXPECT_GT(bright, 2.0 * dark);
}

TEST(LafortuneSelectCli, ReportsEveryCandidateAndRefusesConflicts) {
  using testing_util::ExpectBadInput;
  using testing_util::RunClothfit;
  const fs::path dir = testing_util::FreshTestDir("lafortune_select_");
  const std::string table =
      (fs::path(CLOTHFIT_SHARED_DIR) / "data" / "curet" / "curet_44_linen.csv")
          .string();
  const std::string out = (dir / "p.json").string();
  const testing_util::RunResult r =
      RunClothfit(dir, {"fit", "--model", "lafortune", "--data", table,
                        "--select", "heldout", "--out", out});
  ASSERT_TRUE(r.status == 0 || r.status == 1) << testing_util::Describe(r);
  EXPECT_NE(r.out.find("held-out"), std::string::npos) << r.out;
  const std::string text = testing_util::ReadText(out);
  // One entry per candidate: 4 lobe counts; no lookup-table candidates on
  // CUReT (no view has 16 rows).
  EXPECT_EQ(testing_util::Count(text, "\"heldout_relative_rms\""), 4u) << text;
  for (const std::vector<std::string>& extra :
       {std::vector<std::string>{"--lobes", "2"},
        {"--no-lut"},
        {"--tolerance", "0.1"},
        {"--folds", "1"},
        {"--select", "bic"}}) {
    std::vector<std::string> args = {"fit",     "--model", "lafortune",
                                     "--data",  table,     "--select",
                                     "heldout", "--out",   out + ".x.json"};
    if (extra[0] == "--select")
      args[6] = extra[1];
    else
      args.insert(args.end(), extra.begin(), extra.end());
    ExpectBadInput(dir, args, {});
  }
}

TEST(LafortuneSelectCli, TexelTableChoosesTheMipLevelAndNeedsMip) {
  using testing_util::RunClothfit;
  const fs::path dir = testing_util::FreshTestDir("lafortune_level_");
  const std::string table = (dir / "g.csv").string();
  ASSERT_EQ(RunClothfit(dir, {"synth", "--gonio", "plain", "--texels", "4",
                              "--directions", "4", "--out", table})
                .status,
            0);
  const std::string out = (dir / "m.exr").string();
  testing_util::ExpectBadInput(dir,
                               {"fit", "--model", "lafortune", "--data", table,
                                "--select", "heldout", "--out", out},
                               {"--mip"});
  const testing_util::RunResult r =
      RunClothfit(dir, {"fit", "--model", "lafortune", "--data", table, "--mip",
                        "--select", "heldout", "--out", out});
  ASSERT_TRUE(r.status == 0 || r.status == 1) << testing_util::Describe(r);
  for (const char* level : {"level 0 (4 x 4)", "level 1 (2 x 2)",
                            "level 2 (1 x 1)", "chosen: the lowest"}) {
    EXPECT_NE(r.out.find(level), std::string::npos) << r.out;
  }
  const std::string index = testing_util::ReadText(out + ".json");
  EXPECT_NE(index.find("\"selection\""), std::string::npos);
  EXPECT_EQ(testing_util::Count(index, "\"heldout_relative_rms\""), 3u);
}

}  // namespace
}  // namespace clothfit
