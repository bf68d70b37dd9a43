// Command-line defects a hostile user finds: texel indices that would make
// an enormous texture, arguments that are not options, and standard output
// that cannot be written. Each is exit 2 with one "error:" line, never a
// crash, a dropped argument or a silent exit 0.
#include <gtest/gtest.h>
#include <sys/wait.h>

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
using testing_util::Quote;
using testing_util::ReadText;
using testing_util::RunClothfit;
using testing_util::RunResult;
using testing_util::WriteText;

class CliReliabilityTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing_util::FreshTestDir("cli_reliability_");
  }
  void TearDown() override { fs::remove_all(dir_); }
  // The path of `name` in the test's directory.
  std::string P(const std::string& name) const {
    return (dir_ / name).string();
  }
  fs::path dir_;
};

// One row at texel (s, t): the texture would be (s + 1) x (t + 1) texels
// for one row of data. INT_MAX crashed the fit (the size overflowed) and
// 3000 allocated 6.6 GB of empty texels.
TEST_F(CliReliabilityTest, TexelIndexBeyondTheDataIsBadInput) {
  const std::string header = "theta_i,phi_i,theta_o,phi_o,r,g,b,s,t\n";
  for (const char* st :
       {"2147483647,0", "0,2147483647", "2147483647,2147483647", "3000,3000"}) {
    SCOPED_TRACE(st);
    WriteText(dir_ / "x.csv", header + "30,0,30,180,.1,.1,.1," + st + "\n" +
                                  "40,0,30,180,.1,.1,.1,0,0\n");
    for (const std::vector<std::string>& extra :
         {std::vector<std::string>{}, {"--mip"}, {"--no-lut"}}) {
      std::vector<std::string> args = {"fit",     "--model",  "lafortune",
                                       "--data",  P("x.csv"), "--out",
                                       P("x.exr")};
      args.insert(args.end(), extra.begin(), extra.end());
      ExpectBadInput(dir_, args,
                     {"x.csv:2:", "makes the texture", "than the table's 2"});
    }
  }
}

// A table whose texels each have rows is fitted as before.
TEST_F(CliReliabilityTest, TexelIndicesWithinTheDataAreFitted) {
  std::string table = "theta_i,phi_i,theta_o,phi_o,r,g,b,s,t\n";
  for (int s = 0; s < 2; ++s) {
    for (int i = 0; i < 30; ++i) {
      table += std::to_string(10 + i) + "," + std::to_string(i * 11) + "," +
               std::to_string(20 + i / 2) + "," + std::to_string(180 - i * 3) +
               ",.1,.1,.1," + std::to_string(s) + ",0\n";
    }
  }
  WriteText(dir_ / "x.csv", table);
  const RunResult r =
      RunClothfit(dir_, {"fit", "--model", "lafortune", "--data", P("x.csv"),
                         "--out", P("x.exr"), "--no-lut", "--lobes", "1"});
  EXPECT_TRUE(testing_util::WroteTextureMap(r)) << Describe(r);
}

// Arguments that are not options were dropped: `fit --data a.csv b.csv`
// fitted a.csv alone with exit 0.
TEST_F(CliReliabilityTest, StrayArgumentsAreBadInput) {
  RunResult synth = RunClothfit(dir_, {"synth", "--preset", "linen_plain",
                                       "--rows", "40", "--out", P("a.csv")});
  ASSERT_EQ(synth.status, 0) << Describe(synth);
  fs::copy_file(dir_ / "a.csv", dir_ / "b.csv");
  const std::vector<std::vector<std::string>> commands = {
      {"fit", "--model", "cloth", "--preset", "linen_plain", "--data",
       P("a.csv"), P("b.csv"), "--out", P("o.json")},
      {"fit", "--model", "lafortune", "--data", P("a.csv"), P("b.csv"), "--out",
       P("o.json")},
      {"fit", "--model", "auto", "--data", P("a.csv"), P("b.csv"), "--out",
       P("o.json")},
      {"eval", "--preset", "linen_plain", "--dirs", P("a.csv"), P("b.csv"),
       "--out", P("o.csv")},
      {"synth", "--preset", "linen_plain", "extra", "--out", P("o.csv")},
      {"preset", "linen_plain", "silk_shot"},
      {"presets", "linen_plain"},
      {"version", "now"},
  };
  for (const std::vector<std::string>& args : commands) {
    const std::string stray = args[0] == "synth"     ? "extra"
                              : args[0] == "preset"  ? "silk_shot"
                              : args[0] == "presets" ? "linen_plain"
                              : args[0] == "version" ? "now"
                                                     : P("b.csv");
    ExpectBadInput(dir_, args, {"unexpected argument '" + stray + "'"});
  }
}

// Output to a full disk: what the command printed is lost, so the exit
// status says so (it was 0). Standard output only: no --out names a
// device here.
TEST_F(CliReliabilityTest, FailedWriteOfStandardOutputIsAnError) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  const fs::path err = dir_ / "err.txt";
  for (const std::string args : {"preset linen_plain", "presets", "version",
                                 "--version", "help", "fit --help"}) {
    SCOPED_TRACE(args);
    const std::string command = Quote(CLOTHFIT_BINARY) + " " + args +
                                " </dev/null >/dev/full 2>" +
                                Quote(err.string());
    const int raw = std::system(command.c_str());
    ASSERT_TRUE(raw != -1 && WIFEXITED(raw));
    EXPECT_EQ(WEXITSTATUS(raw), 2);
    const std::string text = ReadText(err);
    EXPECT_EQ(text.rfind("error: standard output: cannot write", 0), 0u)
        << text;
    EXPECT_EQ(testing_util::Count(text, "\n"), 1u) << text;
  }
}

}  // namespace
}  // namespace clothfit
