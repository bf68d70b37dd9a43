// Command-line defects a hostile user finds: texel indices that would make
// an enormous texture, arguments that are not options, and standard output
// that cannot be written. Each is exit 2 with one "error:" line, never a
// crash, a dropped argument or a silent exit 0.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <utility>
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

// A parameter file nested 70,000 levels deep crashed every reader (eval,
// render, fit --init, holes eval); a key given twice was read as its last
// value (a second "model" then reported "key 'tau': unknown key").
TEST_F(CliReliabilityTest, DeepOrRepeatedJsonIsBadInput) {
  RunResult r = RunClothfit(dir_, {"preset", "linen_plain"});
  ASSERT_EQ(r.status, 0) << Describe(r);
  const std::string preset = r.out;
  const size_t close = preset.rfind('}');
  ASSERT_NE(close, std::string::npos);
  WriteText(dir_ / "deep.json", preset.substr(0, close) +
                                    ", \"fit\": " + std::string(70000, '[') +
                                    std::string(70000, ']') + "}\n");
  WriteText(
      dir_ / "deep_objects.json", preset.substr(0, close) + ", \"fit\": " + [] {
        std::string nest;
        for (int i = 0; i < 200000; ++i) nest += "{\"a\":";
        return nest + "1" + std::string(200000, '}');
      }() + "}\n");
  std::string twice = preset;
  twice.replace(twice.find("\"model\": \"cloth\""), 17,
                "\"model\": \"cloth\", \"model\": \"slab\"");
  WriteText(dir_ / "twice.json", twice);
  WriteText(dir_ / "d.csv", "theta_i,phi_i,theta_o,phi_o\n30,0,30,180\n");
  ASSERT_EQ(RunClothfit(dir_, {"synth", "--preset", "linen_plain", "--rows",
                               "40", "--out", P("t.csv")})
                .status,
            0);
  WriteText(dir_ / "mask.pgm", "P2\n2 2\n255\n0 255\n255 0\n");
  for (const char* file : {"deep.json", "deep_objects.json", "twice.json"}) {
    SCOPED_TRACE(file);
    const std::string problem = std::string(file) == "twice.json"
                                    ? "key 'model' appears twice"
                                    : "JSON nested deeper than 64 levels";
    const std::vector<std::vector<std::string>> commands = {
        {"eval", "--params", P(file), "--dirs", P("d.csv"), "--out",
         P("o.csv")},
        {"render", "--params", P(file), "--out", P("r.exr"), "--size", "8"},
        {"fit", "--model", "cloth", "--init", P(file), "--data", P("t.csv"),
         "--out", P("o.json")},
        {"holes", "eval", "--mask", P("mask.pgm"), "--params", P(file),
         "--dirs", P("d.csv"), "--out", P("o.csv")},
    };
    for (const std::vector<std::string>& args : commands) {
      ExpectBadInput(dir_, args, {P(file), problem});
    }
  }
}

// Devices and files without line breaks were read whole: a manifest naming
// /dev/zero as an image never ended, --dirs /dev/zero read 1.2 GB and
// --params /dev/zero 2.2 GB before "out of memory".
TEST_F(CliReliabilityTest, EndlessInputsAreBoundedBadInput) {
  if (!fs::exists("/dev/zero")) GTEST_SKIP() << "no /dev/zero";
  RunResult r = RunClothfit(dir_, {"synth", "--gonio", "plain", "--texels", "2",
                                   "--directions", "2", "--stack", P("m.csv")});
  ASSERT_EQ(r.status, 0) << Describe(r);
  std::string manifest = ReadText(dir_ / "m.csv");
  const size_t image = manifest.find("m_0000.exr");
  ASSERT_NE(image, std::string::npos);
  WriteText(dir_ / "zero.csv", manifest.replace(image, 10, "/dev/zero"));
  ExpectBadInput(
      dir_,
      {"fit", "--model", "lafortune", "--stack", P("zero.csv"), "--out",
       P("z.exr")},
      {"/dev/zero: cannot read image: not a regular file", "zero.csv:"});
  WriteText(dir_ / "d.csv", "theta_i,phi_i,theta_o,phi_o\n30,0,30,180\n");
  ExpectBadInput(dir_,
                 {"eval", "--params", "/dev/zero", "--dirs", P("d.csv"),
                  "--out", P("o.csv")},
                 {"/dev/zero: larger than the 64 MiB limit"});
  ExpectBadInput(dir_,
                 {"eval", "--preset", "linen_plain", "--dirs", "/dev/zero",
                  "--out", P("o.csv")},
                 {"/dev/zero:1: line longer than 1 MiB"});
  // Images each of a readable size that add up to more rows than memory:
  // one 1024 x 1024 image listed 40 times (42 M rows, ~6 GB) is refused
  // before the rows are made.
  {
    std::string pfm = "PF\n1024 1024\n-1.0\n";
    pfm.append(size_t{1024} * 1024 * 3 * sizeof(float), '\0');
    WriteText(dir_ / "big.pfm", pfm);
    std::string many = "# clothfit-stack 1\ntheta_i,phi_i,theta_o,phi_o,file\n";
    for (int i = 0; i < 40; ++i) {
      many += std::to_string(i) + ",0,30,180,big.pfm\n";
    }
    WriteText(dir_ / "many.csv", many);
    ExpectBadInput(dir_,
                   {"fit", "--model", "lafortune", "--stack", P("many.csv"),
                    "--out", P("z.exr")},
                   {"many.csv: 40 images of 1024 x 1024 texels make 41943040 "
                    "rows, more than 33554432"});
  }
  // A long line in a file, after good ones: its line number.
  WriteText(dir_ / "long.csv", "theta_i,phi_i,theta_o,phi_o\n30,0,30,180\n" +
                                   std::string(3 << 20, '1') + "\n");
  ExpectBadInput(dir_,
                 {"eval", "--preset", "linen_plain", "--dirs", P("long.csv"),
                  "--out", P("o.csv")},
                 {"long.csv:3: line longer than 1 MiB"});
}

// Fits that could not be what was asked: a parameter both fixed and free
// (it ran 0 iterations and said "converged"), one measurement repeated
// 100,000 times (exit 0, while 3 such rows were exit 1), a 5-lobe start for
// a fit of at most 3 (the summary said 5, the file held 3).
TEST_F(CliReliabilityTest, ContradictoryFitRequestsAreRefused) {
  ASSERT_EQ(RunClothfit(dir_, {"synth", "--preset", "linen_plain", "--rows",
                               "200", "--out", P("t.csv")})
                .status,
            0);
  ExpectBadInput(dir_,
                 {"fit", "--model", "thread", "--data", P("t.csv"), "--fix",
                  "eta", "--free", "eta", "--out", P("o.json")},
                 {"--fix and --free both name 'eta'"});
  ExpectBadInput(dir_,
                 {"fit", "--model", "thread", "--data", P("t.csv"), "--free",
                  "eta", "--fix", "eta,kd", "--out", P("o.json")},
                 {"--fix and --free both name 'eta'"});
  // A list with an empty item was read without it.
  for (const char* list : {"eta,,kd", "eta,", ",eta"}) {
    ExpectBadInput(dir_,
                   {"fit", "--model", "thread", "--data", P("t.csv"), "--fix",
                    list, "--out", P("o.json")},
                   {"option '--fix': empty item in '" + std::string(list)});
  }
  ExpectBadInput(dir_,
                 {"plot", "--preset", "linen_plain", "--data", P("t.csv"),
                  "--incidence-deg", "1,", "--out", P("p.png")},
                 {"option '--incidence-deg': empty item"});
  // Work beyond what the machine can do in minutes.
  ExpectBadInput(dir_,
                 {"synth", "--preset", "linen_plain", "--rows", "100000000",
                  "--out", P("s.csv")},
                 {"option '--rows': must be in [1, 1e7]"});

  std::string same = "theta_i,phi_i,theta_o,phi_o,value\n";
  for (int i = 0; i < 100000; ++i) same += "30,0,30,180,0.1\n";
  WriteText(dir_ / "same.csv", same);
  const RunResult r = RunClothfit(dir_, {"fit", "--model", "thread", "--data",
                                         P("same.csv"), "--out", P("o.json")});
  EXPECT_EQ(r.status, 1) << Describe(r);
  EXPECT_NE(r.err.find("100000 residual(s) at 1 distinct one(s) cannot "
                       "determine 5 free parameters"),
            std::string::npos)
      << r.err;

  const RunResult lobes = RunClothfit(
      dir_, {"fit", "--model", "lafortune", "--lobes", "3", "--no-lut",
             "--data", P("t.csv"), "--out", P("l3.json")});
  ASSERT_TRUE(fs::exists(dir_ / "l3.json")) << Describe(lobes);
  std::string five = ReadText(dir_ / "l3.json");
  const size_t first = five.find("{", five.find("\"lobes\""));
  const size_t end = five.find("}", first);
  const std::string lobe = five.substr(first, end + 1 - first);
  five.insert(end + 1, ", " + lobe + ", " + lobe);
  WriteText(dir_ / "l5.json", five);
  ExpectBadInput(dir_,
                 {"fit", "--model", "lafortune", "--init", P("l5.json"),
                  "--no-lut", "--data", P("t.csv"), "--out", P("o.json")},
                 {"l5.json: key 'lobes': 5 lobes; the fit fits 0 to 3"});
}

// Parameters whose model is not finite somewhere on the hemisphere wrote
// -nan (thread gamma 1e-300 degrees) and inf (albedo 1e308, a Lafortune lobe
// with |C| = 1e200) with exit 0, from eval, synth and render. The ranges now
// keep every model finite; the check is at the boundary, naming the key.
TEST_F(CliReliabilityTest, ModelsThatAreNotFiniteAreBadInput) {
  WriteText(dir_ / "d.csv", "theta_i,phi_i,theta_o,phi_o\n30,0,30,180\n");
  const std::string thread =
      "{\"model\": \"thread\", \"eta\": 1.46, \"kd\": 0.3, ";
  WriteText(dir_ / "narrow.json",
            thread +
                "\"gamma_s_deg\": 1e-300, \"gamma_v_deg\": 1e-300, "
                "\"albedo\": [0.1, 0.1, 0.1]}");
  WriteText(dir_ / "bright.json",
            thread +
                "\"gamma_s_deg\": 12, \"gamma_v_deg\": 24, "
                "\"albedo\": [1e308, 0.1, 0.1]}");
  const std::string lafortune =
      "{\"model\": \"lafortune\", \"diffuse\": [0.1, 0.1, 0.1], "
      "\"lobes\": [{\"Cy\": [-1, -1, -1], ";
  WriteText(dir_ / "huge.json",
            lafortune +
                "\"Cx\": [-1e200, -1, -1], \"Cz\": [1e200, 1, 1], "
                "\"N\": [2, 2, 2]}]}");
  WriteText(dir_ / "power.json", lafortune +
                                     "\"Cx\": [-3, -1, -1], \"Cz\": [3, 1, 1], "
                                     "\"N\": [500, 2, 2]}]}");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"narrow.json", "key 'gamma_s_deg': must be in [0.01, 90]"},
      {"bright.json", "key 'albedo': component 0 must be in [0, 1000]"},
      {"huge.json", "key 'lobes[0].Cx': component 0 must be in [-1e+100"},
      {"power.json", "key 'lobes[0]': channel 0: max(|Cx|, |Cy|, |Cz|)^N"},
  };
  for (const auto& [file, problem] : cases) {
    SCOPED_TRACE(file);
    ExpectBadInput(dir_,
                   {"eval", "--params", P(file), "--dirs", P("d.csv"), "--out",
                    P("o.csv")},
                   {P(file), problem});
    ExpectBadInput(dir_, {"synth", "--params", P(file), "--out", P("s.csv")},
                   {P(file), problem});
    ExpectBadInput(
        dir_,
        {"render", "--params", P(file), "--out", P("r.exr"), "--size", "8"},
        {P(file), problem});
  }
}

// An image stack with a NaN pixel: the fit exited 1 naming a texel and wrote
// an all-zero map; the image is at fault, and named.
TEST_F(CliReliabilityTest, AnImageWithANanPixelIsBadInput) {
  // Portable float maps (2 x 2 rgb, little-endian, bottom row first).
  auto pfm = [](bool with_nan) {
    std::string bytes = "PF\n2 2\n-1.0\n";
    for (int i = 0; i < 12; ++i) {
      float v = with_nan && i == 4 ? std::nanf("") : 0.1f;
      bytes.append(reinterpret_cast<const char*>(&v), sizeof(v));
    }
    return bytes;
  };
  WriteText(dir_ / "ok.pfm", pfm(false));
  WriteText(dir_ / "nan.pfm", pfm(true));
  WriteText(dir_ / "m.csv",
            "# clothfit-stack 1\n# quantity: cosine_weighted\n"
            "theta_i,phi_i,theta_o,phi_o,file\n30,0,30,180,ok.pfm\n"
            "40,0,30,180,nan.pfm\n");
  ExpectBadInput(dir_,
                 {"fit", "--model", "lafortune", "--stack", P("m.csv"),
                  "--lobes", "1", "--no-lut", "--out", P("p.exr")},
                 {"nan.pfm: pixel (1, 1) channel 1 is NaN", "m.csv:5"});
}

}  // namespace
}  // namespace clothfit
