// Progress on a terminal (apps/progress.h): the line's text, and the
// commands drawing it on a terminal only, never with --quiet or into a
// file or pipe.
#include "apps/progress.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "tests/cli_test_util.h"
#include "tests/io_test_util.h"

namespace clothfit {
namespace {

namespace fs = std::filesystem;
using testing_util::Describe;
using testing_util::Quote;
using testing_util::ReadText;
using testing_util::RunClothfit;
using testing_util::RunResult;

TEST(ProgressLine, ShowsTheShareCountsAndTheTimeLeft) {
  EXPECT_EQ(progress::Line("fit", 512, 1024, "texel fits", 12.0),
            "fit: [##########..........] 512/1024 texel fits, 12 s, about "
            "12 s left");
  // Within the first second: no estimate yet.
  EXPECT_EQ(progress::Line("synth", 1, 4, "texels", 0.4),
            "synth: [#####...............] 1/4 texels, 0 s");
  // Long work in minutes; a quarter done after 5 minutes leaves 15.
  EXPECT_EQ(progress::Line("reading T.csv", 250.5, 1002, "MB", 300.0),
            "reading T.csv: [#####...............] 250.5/1002 MB, 5 min, "
            "about 15 min left");
  // Nothing to do, or done: a full or empty bar, never a division by zero.
  EXPECT_EQ(progress::Line("eval", 0, 0, "rows", 3.0),
            "eval: [....................] 0/0 rows, 3 s");
  EXPECT_EQ(progress::Line("eval", 10, 10, "", 3.0),
            "eval: [####################] 10/10, 3 s");
}

// Runs `clothfit ARGS` on a pseudo-terminal (script(1)); returns what the
// terminal received.
std::string OnTerminal(const fs::path& dir,
                       const std::vector<std::string>& args) {
  std::string command = Quote(CLOTHFIT_BINARY);
  for (const std::string& arg : args) command += " " + Quote(arg);
  const fs::path log = dir / "_terminal.txt";
  const std::string script =
      "script -qefc " + Quote(command) + " " + Quote(log.string()) +
      " </dev/null >" + Quote((dir / "_script_out.txt").string()) + " 2>&1";
  EXPECT_EQ(std::system(script.c_str()), 0) << script;
  return ReadText(log);
}

TEST(ProgressCli, LongWorkShowsProgressOnATerminalOnly) {
  if (std::system("command -v script >/dev/null 2>&1") != 0) {
    GTEST_SKIP() << "script(1) (util-linux) is not installed";
  }
  const fs::path dir = testing_util::FreshTestDir("progress_test_");
  const std::vector<std::string> synth = {
      "synth",    "--gonio", "plain",
      "--texels", "16",      "--directions",
      "8",        "--out",   (dir / "G.csv").string()};
  // On a terminal: the measurement's texels, then the writing's rows,
  // each line erased when done.
  const std::string terminal = OnTerminal(dir, synth);
  EXPECT_NE(terminal.find("synth: ["), std::string::npos) << terminal;
  EXPECT_NE(terminal.find("/256 texels"), std::string::npos) << terminal;
  EXPECT_NE(terminal.find("\r\033[K"), std::string::npos);
  // --quiet: nothing drawn.
  std::vector<std::string> quiet = synth;
  quiet.push_back("--quiet");
  const std::string silent = OnTerminal(dir, quiet);
  EXPECT_EQ(silent.find("synth: ["), std::string::npos) << silent;
  EXPECT_EQ(silent.find('\r'), std::string::npos) << silent;
  // Work of unknown length (one Monte Carlo run): its elapsed time.
  const std::string mc = OnTerminal(
      dir, {"synth", "--model", "slab", "--tau", "0.5", "--albedo", "0.8",
            "--mc", "--photons", "600000", "--out", (dir / "mc.csv").string()});
  EXPECT_NE(mc.find("synth: Monte Carlo ("), std::string::npos) << mc;
  // Into a file: nothing drawn either.
  const RunResult piped = RunClothfit(dir, synth);
  ASSERT_EQ(piped.status, 0) << Describe(piped);
  EXPECT_EQ(piped.err, "");
}

TEST(ProgressCli, WarningsWaitForTheOptionsToBeChecked) {
  // A table that draws a warning, with a bad option after it: the one
  // error line, no warning before it; with good options, the warning.
  const fs::path dir = testing_util::FreshTestDir("progress_test_");
  const std::string data = (dir / "T.csv").string();
  testing_util::WriteText(data,
                          "# scale: arbitrary\n"
                          "theta_i,phi_i,theta_o,phi_o,value\n"
                          "10,0,20,180,0.25\n45,90,60,-90,0.5\n"
                          "70,0,30,0,0.125\n30,45,40,200,0.2\n");
  testing_util::ExpectBadInput(
      dir,
      {"fit", "--model", "thread", "--data", data, "--starts", "0", "--out",
       (dir / "fit.json").string()},
      {"--starts"});
  // The paper's model: the warning is the table's, whichever model is
  // fitted, and the bounded one's quadratures took 3 minutes under the
  // sanitizers for 4 rows.
  const RunResult r =
      RunClothfit(dir, {"fit", "--model", "thread", "--paper-model", "--data",
                        data, "--out", (dir / "fit.json").string()});
  EXPECT_NE(r.err.find("warning: " + data +
                       ": its metadata says 'scale: "
                       "arbitrary'"),
            std::string::npos)
      << Describe(r);
}

}  // namespace
}  // namespace clothfit
