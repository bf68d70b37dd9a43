// clothfit fit --model auto and the cloth freedoms' options from the
// command line: the chosen fit and the table of candidates are written,
// options that do not apply are bad input (exit 2, one error line, nothing
// written).
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "io/params_json.h"
#include "tests/cli_test_util.h"
#include "tests/io_test_util.h"

namespace clothfit {
namespace {

namespace fs = std::filesystem;
using testing_util::Describe;
using testing_util::ExpectBadInput;
using testing_util::ReadText;
using testing_util::RunClothfit;
using testing_util::RunResult;

fs::path TestDir() { return testing_util::FreshTestDir("fit_auto_cli_test_"); }

// The paper's model (--paper-model on synth and fit), which takes seconds:
// the bounded default is FabricSelect.PlainWeaveClothIsChosenForAPlain-
// WeaveTable's (minutes).
TEST(FitAutoCli, WritesTheChosenFitAndTheCandidatesBesideIt) {
  const fs::path dir = TestDir();
  const std::string table = (dir / "linen.csv").string();
  ASSERT_EQ(
      RunClothfit(dir, {"synth", "--preset", "linen_plain", "--rows", "120",
                        "--noise", "0.02", "--paper-model", "--out", table})
          .status,
      0);
  const std::string out = (dir / "auto.json").string();
  const RunResult r = RunClothfit(dir, {"fit", "--model", "auto", "--data",
                                        table, "--paper-model", "--out", out});
  ASSERT_EQ(r.status, 0) << Describe(r);
  EXPECT_NE(r.out.find("model selection (held-out error)"), std::string::npos)
      << r.out;
  const ParamFile fitted = ReadParamFile(out);
  ASSERT_TRUE(std::holds_alternative<ClothParams>(fitted.params));
  EXPECT_EQ(std::get<ClothParams>(fitted.params).energy_bound, nullptr);
  EXPECT_NE(fitted.fit_json.find("\"selection\""), std::string::npos);
  const std::string csv = ReadText(dir / "auto.candidates.csv");
  EXPECT_EQ(csv.rfind("candidate,free_parameters,relative_rms,"
                      "heldout_relative_rms,bic,seconds,converged,chosen,",
                      0),
            0u)
      << csv;
  // One header and one line per candidate, exactly one chosen.
  size_t lines = 0, chosen = 0;
  for (size_t p = 0; (p = csv.find('\n', p)) != std::string::npos; ++p) {
    ++lines;
  }
  for (size_t p = 0; (p = csv.find(",yes,\"", p)) != std::string::npos; ++p) {
    ++chosen;
  }
  EXPECT_EQ(lines, 1u + 9u) << csv;  // 9 candidates (docs/fitting.md)
  EXPECT_EQ(chosen, 1u) << csv;
}

TEST(FitAutoCli, OptionsThatDoNotApplyAreBadInput) {
  const fs::path dir = TestDir();
  const std::string table = (dir / "t.csv").string();
  ASSERT_EQ(RunClothfit(dir, {"synth", "--preset", "linen_plain", "--rows",
                              "40", "--out", table})
                .status,
            0);
  const std::string out = (dir / "o.json").string();
  ExpectBadInput(dir,
                 {"fit", "--model", "auto", "--data", table, "--preset",
                  "linen_plain", "--out", out},
                 {"--preset", "auto"});
  ExpectBadInput(
      dir,
      {"fit", "--model", "auto", "--data", table, "--folds", "1", "--out", out},
      {"--folds"});
  ExpectBadInput(dir,
                 {"fit", "--model", "thread", "--data", table, "--folds", "3",
                  "--out", out},
                 {"--folds"});
  ExpectBadInput(dir,
                 {"fit", "--model", "thread", "--data", table, "--also-free",
                  "diffuse", "--out", out},
                 {"--also-free", "cloth"});
  ExpectBadInput(dir,
                 {"fit", "--model", "cloth", "--preset", "linen_plain",
                  "--data", table, "--also-free", "rotation", "--out", out},
                 {"--also-free", "'rotation'"});
  ExpectBadInput(dir,
                 {"fit", "--model", "cloth", "--preset", "linen_plain",
                  "--data", table, "--design-points", "-1", "--out", out},
                 {"--design-points"});
}

}  // namespace
}  // namespace clothfit
