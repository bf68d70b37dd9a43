// Held-out model selection for Lafortune fits (fit --select heldout):
// k-fold over the table's lights, each candidate scored on lights it never
// saw.
#include "fitting/lafortune_select.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

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
  // CUReT (no view has 8 rows).
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

}  // namespace
}  // namespace clothfit
