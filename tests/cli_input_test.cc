// Input as a person writes it, through the command line: names that are
// nearly right get a suggestion, tables that look misread get a warning,
// and numbers come back as they were written.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

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
using testing_util::WriteText;

fs::path TestDir() { return testing_util::FreshTestDir("cli_input_test_"); }

const fs::path kLinen =
    fs::path(CLOTHFIT_SHARED_DIR) / "data" / "curet" / "curet_44_linen.csv";

TEST(CliInput, NearlyRightNamesGetASuggestion) {
  const fs::path dir = TestDir();
  const std::string data = kLinen.string();
  const std::string out = (dir / "fit.json").string();
  ExpectBadInput(dir,
                 {"fit", "--model", "lafortune", "--data", data, "--lobe", "2",
                  "--out", out},
                 {"unknown option '--lobe'", "(did you mean '--lobes'?)"});
  ExpectBadInput(dir,
                 {"fit", "--model", "lafourtune", "--data", data, "--out", out},
                 {"'lafourtune'", "(did you mean 'lafortune'?)"});
  ExpectBadInput(dir, {"preset", "linen"},
                 {"unknown preset 'linen'", "(did you mean 'linen_plain'?)"});
  ExpectBadInput(dir, {"synth", "--preset", "velvett", "--out", out},
                 {"(did you mean 'velvet'?)"});
  ExpectBadInput(dir, {"fti", "--model", "thread"},
                 {"unknown command 'fti'", "(did you mean 'fit'?)"});
  // Nothing close: no suggestion.
  const RunResult far = RunClothfit(dir, {"preset", "qqqqqq"});
  EXPECT_EQ(far.status, 2);
  EXPECT_EQ(far.err.find("did you mean"), std::string::npos) << far.err;
}

TEST(CliInput, RadiansReadAsDegreesAreWarnedAboutByTheCommands) {
  const fs::path dir = TestDir();
  const std::string data = (dir / "T.csv").string();
  WriteText(data,
            "theta_i,phi_i,theta_o,phi_o,value\n"
            "0.17,0,0.35,3.14,0.25\n0.79,1.57,1.05,-1.57,0.5\n"
            "1.22,0,0.52,0,0.1\n0.5,0.2,0.6,3,0.3\n");
  const std::string out = (dir / "E.csv").string();
  const RunResult r = RunClothfit(
      dir, {"eval", "--preset", "linen_plain", "--dirs", data, "--out", out});
  ASSERT_EQ(r.status, 0) << Describe(r);
  EXPECT_NE(r.err.find("warning: " + data +
                       ": every angle is within the range of radians"),
            std::string::npos)
      << r.err;
  // Said in the column names: read as radians, no warning.
  WriteText(data,
            "theta_i [rad],phi_i [rad],theta_o [rad],phi_o [rad],value\n"
            "0.17,0,0.35,3.14,0.25\n0.79,1.57,1.05,-1.57,0.5\n");
  const RunResult named = RunClothfit(
      dir, {"eval", "--preset", "linen_plain", "--dirs", data, "--out", out});
  ASSERT_EQ(named.status, 0) << Describe(named);
  EXPECT_EQ(named.err, "");
}

TEST(CliInput, ArbitraryScaleTablesPointToFitScale) {
  const fs::path dir = TestDir();
  const std::string out = (dir / "fit.json").string();
  // CUReT's metadata says "arbitrary common scale": a thread fit without
  // --fit-scale is warned before it runs and, far from the data, hinted at.
  const RunResult r =
      RunClothfit(dir, {"fit", "--model", "thread", "--data", kLinen.string(),
                        "--starts", "1", "--out", out});
  EXPECT_NE(r.err.find("warning: " + kLinen.string() +
                       ": its metadata says 'sample: CUReT sample 44 (linen), "
                       "RGB-averaged, arbitrary common scale'"),
            std::string::npos)
      << Describe(r);
  EXPECT_NE(r.err.find("--fit-scale"), std::string::npos) << r.err;
  const RunResult scaled =
      RunClothfit(dir, {"fit", "--model", "thread", "--data", kLinen.string(),
                        "--starts", "1", "--fit-scale", "--out", out});
  EXPECT_EQ(scaled.err.find("arbitrary"), std::string::npos) << scaled.err;
  EXPECT_EQ(scaled.err.find("hint:"), std::string::npos) << scaled.err;
}

TEST(CliInput, SpreadsheetTablesAreReadByTheCommands) {
  const fs::path dir = TestDir();
  const std::string data = (dir / "T.csv").string();
  // A spreadsheet's export: semicolons, decimal commas, quoted names with
  // units.
  WriteText(data,
            "\"theta_i [deg]\";\"phi_i [deg]\";\"theta_o [deg]\";"
            "\"phi_o [deg]\";\"value [%]\"\n"
            "30;0;60;180;25,5\n45;90;20;-90;12,25\n");
  const std::string out = (dir / "E.csv").string();
  const RunResult r = RunClothfit(
      dir, {"eval", "--preset", "linen_plain", "--dirs", data, "--out", out});
  ASSERT_EQ(r.status, 0) << Describe(r);
  const std::string text = ReadText(out);
  // Written back in clothfit's form: commas, degrees exactly as read.
  EXPECT_NE(text.find("\n30,0,60,180,"), std::string::npos) << text;
  EXPECT_NE(text.find("\n45,90,20,-90,"), std::string::npos) << text;
}

TEST(CliInput, TheSummarySaysConvergedOrNotBeforeTheSolversWord) {
  const fs::path dir = TestDir();
  const std::string out = (dir / "fit.json").string();
  // One iteration: the solver stops at its limit; the summary's verdict
  // comes first, in words, and the solver's own term after it.
  const RunResult r =
      RunClothfit(dir, {"fit", "--model", "thread", "--data", kLinen.string(),
                        "--fit-scale", "--max-iterations", "1", "--out", out});
  EXPECT_EQ(r.status, 1) << Describe(r);
  EXPECT_EQ(r.out.rfind("fit: not converged (the 'reason' line says why); "
                        "solver: ",
                        0),
            0u)
      << r.out;
  EXPECT_EQ(r.out.find("usable, not converged"), std::string::npos);
  EXPECT_NE(r.err.find("error: the fit did not converge: "), std::string::npos)
      << r.err;
  // Two lobes without a lookup table are not "one lobe".
  const RunResult lobes =
      RunClothfit(dir, {"fit", "--model", "lafortune", "--lobes", "2",
                        "--no-lut", "--data", kLinen.string(), "--out", out});
  EXPECT_EQ(lobes.status, 0) << Describe(lobes);
  EXPECT_NE(lobes.out.find("no lookup table: the lobes in one solve"),
            std::string::npos)
      << lobes.out;
  EXPECT_EQ(lobes.out.find("one lobe"), std::string::npos) << lobes.out;
}

TEST(CliInput, HelpPrintsNumbersAsPeopleWriteThem) {
  const fs::path dir = TestDir();
  for (const char* command : {"fit", "synth", "eval", "export", "bench"}) {
    const RunResult r = RunClothfit(dir, {command, "--help"});
    ASSERT_EQ(r.status, 0) << command;
    // No double printed at 17 digits (0.35 as 0.34999999999999998).
    EXPECT_EQ(r.out.find("9999999"), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("0000000"), std::string::npos) << r.out;
  }
}

// A table file for one Lafortune model is read row by row, once for the
// samples and once for the rows' errors; a pipe, which can be read only
// once, is held in memory. Both give the same model, and a row skipped as
// invalid is warned about once, not once a pass.
TEST(CliInput, LafortuneFitOfAFileReadTwiceEqualsTheFitOfAPipe) {
  const fs::path dir = TestDir();
  const fs::path table = dir / "linen.csv";
  WriteText(table, ReadText(kLinen) + "10,0,20,180,x\n");
  const std::vector<std::string> fit = {"fit",           "--model", "lafortune",
                                        "--lobes",       "2",       "--no-lut",
                                        "--skip-invalid"};
  std::vector<std::string> from_file = fit;
  for (const std::string& arg :
       {std::string("--data"), table.string(), std::string("--out"),
        (dir / "file.json").string()}) {
    from_file.push_back(arg);
  }
  const RunResult file = RunClothfit(dir, from_file);
  ASSERT_EQ(file.status, 0) << Describe(file);
  EXPECT_EQ(testing_util::Count(file.err, "skipped 1 invalid row"), 1u)
      << file.err;
  std::string command = "cat " + testing_util::Quote(table.string()) + " | " +
                        testing_util::Quote(CLOTHFIT_BINARY);
  for (const std::string& arg : fit) command += " " + testing_util::Quote(arg);
  command += " --data /dev/stdin --out " +
             testing_util::Quote((dir / "pipe.json").string()) +
             " >/dev/null 2>" +
             testing_util::Quote((dir / "pipe.err").string());
  ASSERT_EQ(std::system(command.c_str()), 0) << ReadText(dir / "pipe.err");
  EXPECT_EQ(
      testing_util::Count(ReadText(dir / "pipe.err"), "skipped 1 invalid row"),
      1u);
  const std::string model = ReadText(dir / "file.json");
  EXPECT_NE(model.find("\"relative_rms\""), std::string::npos);
  EXPECT_EQ(model, ReadText(dir / "pipe.json"));
}

}  // namespace
}  // namespace clothfit
