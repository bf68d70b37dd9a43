// Runs the clothfit executable (docs/cli.md) and checks its files, output and
// exit status against the library.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <glm/geometric.hpp>
#include <initializer_list>
#include <iterator>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "fitting/lafortune_mip.h"
#include "io/atomic_file.h"
#include "io/param_mipmap.h"
#include "io/params_json.h"
#include "io/table.h"
#include "models/bounded.h"
#include "models/evaluate.h"
#include "models/presets.h"
#include "tests/cli_test_util.h"
#include "tests/io_test_util.h"

namespace clothfit {
namespace {

namespace fs = std::filesystem;

constexpr double kPi = 3.14159265358979323846;

using testing_util::Count;
using testing_util::Describe;
using testing_util::ExpectBadInput;
using testing_util::FilesIn;
using testing_util::ReadText;
using testing_util::RunClothfit;
using testing_util::RunResult;
using testing_util::WriteText;
using testing_util::WroteTextureMap;

fs::path TestDir() { return testing_util::FreshTestDir("cli_test_"); }

ClothParams Preset(const std::string& name) {
  ClothParams c;
  EXPECT_TRUE(GetPreset(name, &c)) << name;
  return c;
}

// |actual - expected| <= tolerance * |expected| per channel (so an expected
// 0 must be matched exactly).
void ExpectRelativelyNear(const glm::dvec3& actual, const glm::dvec3& expected,
                          double tolerance, const std::string& where) {
  for (int c = 0; c < 3; ++c) {
    EXPECT_LE(std::abs(actual[c] - expected[c]),
              tolerance * std::abs(expected[c]))
        << where << " channel " << c << ": " << actual[c] << " vs "
        << expected[c];
  }
}

// Direction pairs for eval: a grid over both hemispheres (wo also below the
// surface when `lower_wo`), mirror configurations that hit the specular
// peaks, and grazing and exactly horizontal directions.
MeasurementTable DirectionTable(bool lower_wo) {
  MeasurementTable table;
  table.direction_columns = DirectionColumns::kVectors;
  table.channels = 3;
  auto add = [&](const glm::dvec3& wi, const glm::dvec3& wo) {
    TableRow row;
    row.wi = glm::normalize(wi);
    row.wo = glm::normalize(wo);
    table.rows.push_back(row);
  };
  const double deg = kPi / 180.0;
  for (double theta_i : {0.0, 20.0, 45.0, 70.0, 89.9}) {
    for (double phi_i : {0.0, 60.0, 135.0}) {
      const glm::dvec3 wi = DirectionFromAngles(theta_i * deg, phi_i * deg);
      // Mirror direction and a nearby off-specular one.
      add(wi, glm::dvec3(-wi.x, -wi.y, wi.z));
      add(wi, DirectionFromAngles((theta_i * 0.5 + 10.0) * deg,
                                  (phi_i + 170.0) * deg));
      add(wi, DirectionFromAngles(33.0 * deg, (phi_i + 40.0) * deg));
    }
  }
  // Grazing and horizontal.
  add({1.0, 0.0, 0.0}, {-1.0, 0.0, 0.0});
  add({1.0, 0.0, 0.0}, {0.0, 0.6, 0.8});
  add({0.0, 0.6, 0.8}, {0.0, -1.0, 0.0});
  add(DirectionFromAngles(89.99 * deg, 10.0 * deg),
      DirectionFromAngles(89.99 * deg, 190.0 * deg));
  add({0.0, 0.0, 1.0}, {0.0, 0.0, 1.0});
  add({0.3, -0.2, 0.9}, {-0.31, 0.19, 0.9});
  if (lower_wo) {
    add({0.3, 0.1, 0.9}, {0.2, 0.3, -0.9});
    add({0.0, 0.5, 0.8}, {0.1, -0.4, -0.8});
    add({0.7, 0.0, 0.7}, {0.7, 0.0, -0.7});
    add({0.2, 0.2, 0.95}, {0.0, 0.0, -1.0});
  } else {
    add({0.3, 0.1, 0.9}, {0.2, 0.3, 0.9});
    add({0.0, 0.5, 0.8}, {0.1, -0.4, 0.8});
    add({0.7, 0.0, 0.7}, {0.7, 0.0, 0.7});
    add({0.2, 0.2, 0.95}, {0.0, 0.0, 1.0});
  }
  return table;
}

// Runs eval for `params_path` at the directions of `table` for both
// quantities and compares every value with Evaluate(expected, ...).
void CheckEval(const fs::path& dir, const fs::path& params_path,
               const MeasurementTable& table, const ModelParams& expected) {
  const fs::path dirs_path = dir / "D.csv";
  WriteTable(table, dirs_path.string());
  ReadTableOptions read_options;
  read_options.values_optional = true;
  // The directions as eval reads them (normalised on read).
  const MeasurementTable dirs =
      ReadTable(dirs_path.string(), read_options).table;
  ASSERT_EQ(dirs.rows.size(), table.rows.size());

  for (Quantity quantity : {Quantity::kBrdf, Quantity::kCosineWeighted}) {
    const std::string name = QuantityName(quantity);
    const fs::path out_path = dir / ("O_" + name + ".csv");
    const RunResult r =
        RunClothfit(dir, {"eval", "--params", params_path.string(), "--dirs",
                          dirs_path.string(), "--out", out_path.string(),
                          "--quantity", name});
    ASSERT_EQ(r.status, 0) << Describe(r);
    EXPECT_EQ(r.err, "");
    const MeasurementTable out = ReadTable(out_path.string()).table;
    EXPECT_EQ(out.quantity, quantity);
    EXPECT_EQ(out.channels, 3);
    ASSERT_EQ(out.rows.size(), dirs.rows.size());
    int nonzero = 0;
    for (size_t i = 0; i < out.rows.size(); ++i) {
      const std::string where = name + " row " + std::to_string(i);
      const TableRow& row = out.rows[i];
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(row.wi[c], dirs.rows[i].wi[c], 1e-15) << where;
        EXPECT_NEAR(row.wo[c], dirs.rows[i].wo[c], 1e-15) << where;
      }
      const glm::dvec3 want =
          Evaluate(expected, dirs.rows[i].wi, dirs.rows[i].wo, quantity);
      ExpectRelativelyNear(row.value, want, 1e-12, where);
      if (want.x != 0.0) ++nonzero;
    }
    // Most rows must carry a real value for the comparison to mean much.
    EXPECT_GT(nonzero, static_cast<int>(out.rows.size()) / 2) << name;
  }
}

TEST(CliTest, PresetsListsSixNames) {
  const fs::path dir = TestDir();
  const RunResult r = RunClothfit(dir, {"presets"});
  ASSERT_EQ(r.status, 0) << Describe(r);
  std::string expected;
  for (const char* name :
       {"linen_plain", "silk_crepe_de_chine", "polyester_satin_charmeuse",
        "polyester_satin_charmeuse_back", "silk_shot", "velvet"}) {
    expected += std::string(name) + "\n";
  }
  EXPECT_EQ(r.out, expected);
  EXPECT_EQ(r.err, "");
}

TEST(CliTest, PresetPrintsParameterFileOfLibraryPreset) {
  const fs::path dir = TestDir();
  const RunResult r = RunClothfit(dir, {"preset", "linen_plain"});
  ASSERT_EQ(r.status, 0) << Describe(r);
  EXPECT_EQ(r.err, "");
  const ParamFile file = ParseParamFile(r.out, "stdout");
  const ClothParams expected = Preset("linen_plain");
  EXPECT_EQ(r.out, FormatParamFile(ParamFile{expected, ""}));
  ASSERT_TRUE(std::holds_alternative<ClothParams>(file.params));
  const ClothParams& got = std::get<ClothParams>(file.params);
  ASSERT_EQ(got.threads.size(), expected.threads.size());
  for (size_t j = 0; j < got.threads.size(); ++j) {
    const ClothThread& a = got.threads[j];
    const ClothThread& b = expected.threads[j];
    EXPECT_EQ(a.direction, b.direction) << j;
    EXPECT_EQ(a.coverage, b.coverage) << j;
    EXPECT_EQ(a.offsets_deg, b.offsets_deg) << j;
    EXPECT_EQ(a.params.eta, b.params.eta) << j;
    EXPECT_EQ(a.params.kd, b.params.kd) << j;
    EXPECT_EQ(a.params.gamma_s_deg, b.params.gamma_s_deg) << j;
    EXPECT_EQ(a.params.gamma_v_deg, b.params.gamma_v_deg) << j;
    EXPECT_EQ(a.params.albedo, b.params.albedo) << j;
  }
}

TEST(CliTest, PresetOutWritesSameFileAsStdout) {
  const fs::path dir = TestDir();
  const fs::path path = dir / "P.json";
  const RunResult r =
      RunClothfit(dir, {"preset", "velvet", "--out", path.string()});
  ASSERT_EQ(r.status, 0) << Describe(r);
  EXPECT_EQ(r.out, "");
  EXPECT_EQ(ReadText(path), FormatParamFile(ParamFile{Preset("velvet"), ""}));
}

TEST(CliTest, EvalPresetMatchesLibrary) {
  const fs::path dir = TestDir();
  const fs::path params_path = dir / "P.json";
  const RunResult r =
      RunClothfit(dir, {"preset", "silk_shot", "--out", params_path.string()});
  ASSERT_EQ(r.status, 0) << Describe(r);
  const MeasurementTable table = DirectionTable(/*lower_wo=*/false);
  ASSERT_GE(table.rows.size(), 50u);
  CheckEval(dir, params_path, table, Preset("silk_shot"));
}

TEST(CliTest, EvalThreadFileMatchesLibrary) {
  const fs::path dir = TestDir();
  ThreadParams p;
  p.eta = 1.539;
  p.kd = 0.1;
  p.gamma_s_deg = 2.5;
  p.gamma_v_deg = 5.0;
  p.albedo = glm::dvec3(0.035, 0.01295, 0.0105);
  const fs::path params_path = dir / "thread.json";
  WriteParamFile(ParamFile{p, ""}, params_path.string());
  // Thread tables: wo may lie below the thread's local normal plane.
  CheckEval(dir, params_path, DirectionTable(/*lower_wo=*/true), p);
}

TEST(CliTest, SynthWithoutNoiseMatchesLibrary) {
  const fs::path dir = TestDir();
  const fs::path path = dir / "T.csv";
  const RunResult r =
      RunClothfit(dir, {"synth", "--preset", "silk_shot", "--rows", "300",
                        "--noise", "0", "--seed", "3", "--out", path.string()});
  ASSERT_EQ(r.status, 0) << Describe(r);
  const MeasurementTable table = ReadTable(path.string()).table;
  ASSERT_EQ(table.rows.size(), 300u);
  EXPECT_EQ(table.quantity, Quantity::kBrdf);
  EXPECT_EQ(table.channels, 3);
  EXPECT_FALSE(table.has_sigma);
  // The bounded preset, which synth draws by default.
  const ModelParams preset = WithEnergyBound(Preset("silk_shot"));
  int nonzero = 0;
  for (size_t i = 0; i < table.rows.size(); ++i) {
    const TableRow& row = table.rows[i];
    EXPECT_GE(row.wi.z, 0.0) << i;
    EXPECT_GE(row.wo.z, 0.0) << i;
    ExpectRelativelyNear(row.value,
                         Evaluate(preset, row.wi, row.wo, Quantity::kBrdf),
                         1e-9, "row " + std::to_string(i));
    if (row.value.y != 0.0) ++nonzero;
  }
  EXPECT_GT(nonzero, 250);
}

TEST(CliTest, SynthIsDeterministic) {
  const fs::path dir = TestDir();
  const std::vector<std::string> args = {
      "synth",   "--preset", "silk_shot", "--rows", "300",
      "--noise", "0",        "--seed",    "3",      "--out"};
  std::vector<std::string> first = args, second = args, other = args;
  first.push_back((dir / "T1.csv").string());
  second.push_back((dir / "T2.csv").string());
  other.push_back((dir / "T3.csv").string());
  other[8] = "4";  // a different seed
  ASSERT_EQ(RunClothfit(dir, first).status, 0);
  ASSERT_EQ(RunClothfit(dir, second).status, 0);
  ASSERT_EQ(RunClothfit(dir, other).status, 0);
  const std::string a = ReadText(dir / "T1.csv");
  EXPECT_FALSE(a.empty());
  EXPECT_EQ(a, ReadText(dir / "T2.csv"));
  EXPECT_NE(a, ReadText(dir / "T3.csv"));
}

TEST(CliTest, SynthNoiseIsAboutTheRequestedLevel) {
  const fs::path dir = TestDir();
  const fs::path clean_path = dir / "clean.csv";
  const fs::path noisy_path = dir / "noisy.csv";
  ASSERT_EQ(RunClothfit(dir, {"synth", "--preset", "silk_shot", "--rows", "300",
                              "--noise", "0", "--seed", "3", "--out",
                              clean_path.string()})
                .status,
            0);
  const RunResult r = RunClothfit(
      dir, {"synth", "--preset", "silk_shot", "--rows", "300", "--noise",
            "0.02", "--seed", "3", "--out", noisy_path.string()});
  ASSERT_EQ(r.status, 0) << Describe(r);
  const MeasurementTable clean = ReadTable(clean_path.string()).table;
  const MeasurementTable noisy = ReadTable(noisy_path.string()).table;
  EXPECT_TRUE(noisy.has_sigma);
  EXPECT_NE(ReadText(noisy_path).find("sigma_r,sigma_g,sigma_b"),
            std::string::npos);
  ASSERT_EQ(noisy.rows.size(), 300u);
  ASSERT_EQ(clean.rows.size(), noisy.rows.size());
  // The sigma floor: 1 % of the channel's median clean value (the fits'
  // default relative noise floor; a value of 0 keeps a finite sigma).
  glm::dvec3 floor(0.0);
  for (int c = 0; c < 3; ++c) {
    std::vector<double> v;
    for (const TableRow& row : clean.rows) v.push_back(std::abs(row.value[c]));
    std::sort(v.begin(), v.end());
    floor[c] = 0.01 * v[v.size() / 2];
    EXPECT_GT(floor[c], 0.0);
  }
  double sum2 = 0.0;
  int count = 0;
  int floored = 0;
  for (size_t i = 0; i < noisy.rows.size(); ++i) {
    const TableRow& a = clean.rows[i];
    const TableRow& b = noisy.rows[i];
    // The same seed draws the same directions.
    for (int c = 0; c < 3; ++c) {
      ASSERT_EQ(a.wi[c], b.wi[c]) << i;
      ASSERT_EQ(a.wo[c], b.wo[c]) << i;
    }
    for (int c = 0; c < 3; ++c) {
      if (a.value[c] == 0.0) {
        EXPECT_EQ(b.value[c], 0.0) << i;
        EXPECT_NEAR(b.sigma[c], 0.02 * floor[c], 1e-12 * floor[c]) << i;
        continue;
      }
      const double deviation = b.value[c] / a.value[c] - 1.0;
      sum2 += deviation * deviation;
      ++count;
      // sigma = noise * max(|clean value|, floor)
      // (data_synthetic/synthetic_table.h).
      const double sigma = 0.02 * std::max(std::abs(a.value[c]), floor[c]);
      floored += std::abs(a.value[c]) < floor[c];
      EXPECT_NEAR(b.sigma[c], sigma, 1e-12 * sigma) << i;
    }
  }
  ASSERT_GT(count, 600);
  EXPECT_LT(floored, count / 10);
  const double rms = std::sqrt(sum2 / count);
  EXPECT_GE(rms, 0.01);
  EXPECT_LE(rms, 0.03);
}

TEST(CliTest, HelpOnEveryCommand) {
  const fs::path dir = TestDir();
  for (const char* command : {"eval", "preset", "presets", "synth"}) {
    const RunResult r = RunClothfit(dir, {command, "--help"});
    EXPECT_EQ(r.status, 0) << command << "\n" << Describe(r);
    EXPECT_NE(r.out.find("usage:"), std::string::npos) << command;
    EXPECT_NE(r.out.find(command), std::string::npos) << command;
    EXPECT_EQ(r.err, "") << command;
  }
  const RunResult top = RunClothfit(dir, {"--help"});
  EXPECT_EQ(top.status, 0) << Describe(top);
  EXPECT_NE(top.out.find("usage:"), std::string::npos);
}

TEST(CliTest, VersionPrintsTheProjectVersion) {
  const fs::path dir = TestDir();
  // CLOTHFIT_VERSION is CMake's project(VERSION ...): three numbers.
  const std::string version = CLOTHFIT_VERSION;
  int parts = 0;
  std::stringstream ss(version);
  for (std::string part; std::getline(ss, part, '.'); ++parts) {
    EXPECT_FALSE(part.empty()) << version;
    EXPECT_EQ(part.find_first_not_of("0123456789"), std::string::npos)
        << version;
  }
  EXPECT_EQ(parts, 3) << version;
  for (const char* form : {"--version", "version"}) {
    const RunResult r = RunClothfit(dir, {form});
    EXPECT_EQ(r.status, 0) << form << "\n" << Describe(r);
    EXPECT_EQ(r.out, "clothfit " + version + "\n") << form;
    EXPECT_EQ(r.err, "") << form;
  }
  const RunResult top = RunClothfit(dir, {"--help"});
  EXPECT_NE(top.out.find("--version"), std::string::npos) << top.out;
  EXPECT_NE(top.out.find("help <command>"), std::string::npos) << top.out;
  ExpectBadInput(dir, {"version", "extra"}, {"version", "extra"});
}

// clothfit help CMD [ARGS] prints what clothfit CMD [ARGS] --help prints.
TEST(CliTest, HelpCommandPrintsTheCommandsHelp) {
  const fs::path dir = TestDir();
  // Plain commands, commands whose help depends on their arguments, and a
  // subcommand.
  const std::vector<std::vector<std::string>> commands = {
      {"eval"},
      {"fit", "--model", "lafortune"},
      {"synth", "--model", "slab"},
      {"holes", "eval"},
      {"version"}};
  for (const std::vector<std::string>& command : commands) {
    std::vector<std::string> direct = command;
    direct.push_back("--help");
    std::vector<std::string> via_help = {"help"};
    via_help.insert(via_help.end(), command.begin(), command.end());
    const RunResult want = RunClothfit(dir, direct);
    const RunResult got = RunClothfit(dir, via_help);
    const std::string what = command[0] + (command.size() > 1 ? " ..." : "");
    EXPECT_EQ(want.status, 0) << what << "\n" << Describe(want);
    EXPECT_EQ(got.status, 0) << what << "\n" << Describe(got);
    EXPECT_NE(want.out.find("usage:"), std::string::npos) << what;
    EXPECT_EQ(got.out, want.out) << what;
    EXPECT_EQ(got.err, "") << what;
  }
  // The help texts differ, so the comparison above tells commands apart.
  EXPECT_NE(RunClothfit(dir, {"help", "eval"}).out,
            RunClothfit(dir, {"help", "fit"}).out);
  // 'help' alone is the general usage.
  const RunResult usage = RunClothfit(dir, {"help"});
  EXPECT_EQ(usage.status, 0);
  EXPECT_EQ(usage.out, RunClothfit(dir, {"--help"}).out);
  ExpectBadInput(dir, {"help", "nosuch"}, {"help", "'nosuch'", "eval"});
}

// A directory with a valid P.json (linen) and D.csv (a few directions).
fs::path DirWithInputs() {
  const fs::path dir = TestDir();
  WriteParamFile(ParamFile{Preset("linen_plain"), ""},
                 (dir / "P.json").string());
  MeasurementTable table = DirectionTable(false);
  table.rows.resize(5);
  WriteTable(table, (dir / "D.csv").string());
  return dir;
}

TEST(CliTest, EvalInputsOfDirWithInputsAreAccepted) {
  // Guards the bad-input tests below: the same command with good inputs
  // succeeds.
  const fs::path dir = DirWithInputs();
  const RunResult r = RunClothfit(
      dir, {"eval", "--params", (dir / "P.json").string(), "--dirs",
            (dir / "D.csv").string(), "--out", (dir / "O.csv").string()});
  EXPECT_EQ(r.status, 0) << Describe(r);
  EXPECT_TRUE(fs::exists(dir / "O.csv"));
}

TEST(CliTest, EvalMissingParamsFile) {
  const fs::path dir = DirWithInputs();
  const std::string missing = (dir / "no_such_params.json").string();
  ExpectBadInput(dir,
                 {"eval", "--params", missing, "--dirs",
                  (dir / "D.csv").string(), "--out", (dir / "O.csv").string()},
                 {missing});
}

TEST(CliTest, EvalParamsWithUnknownKey) {
  const fs::path dir = DirWithInputs();
  const fs::path params = dir / "bad.json";
  WriteText(params,
            "{\"model\": \"thread\", \"eta\": 1.5, \"kd\": 0.1, "
            "\"gamma_s_deg\": 2.5, \"gamma_v_deg\": 5, \"albedo\": 0.1, "
            "\"shininess\": 3}\n");
  ExpectBadInput(dir,
                 {"eval", "--params", params.string(), "--dirs",
                  (dir / "D.csv").string(), "--out", (dir / "O.csv").string()},
                 {"shininess", params.string()});
}

TEST(CliTest, EvalDirsWithUnparsableNumber) {
  const fs::path dir = DirWithInputs();
  const fs::path dirs = dir / "bad_dirs.csv";
  WriteText(dirs,
            "# clothfit-table 1\n"
            "theta_i,phi_i,theta_o,phi_o\n"
            "10,20,30,40\n"
            "10,20,3x0,40\n");
  ExpectBadInput(dir,
                 {"eval", "--params", (dir / "P.json").string(), "--dirs",
                  dirs.string(), "--out", (dir / "O.csv").string()},
                 {dirs.string() + ":4", "theta_o", "3x0"});
}

TEST(CliTest, UnknownOption) {
  const fs::path dir = DirWithInputs();
  ExpectBadInput(dir,
                 {"eval", "--params", (dir / "P.json").string(), "--dirs",
                  (dir / "D.csv").string(), "--out", (dir / "O.csv").string(),
                  "--colour", "red"},
                 {"--colour"});
}

TEST(CliTest, UnknownCommand) {
  const fs::path dir = TestDir();
  ExpectBadInput(dir, {"frobnicate", "--out", (dir / "O.csv").string()},
                 {"frobnicate"});
}

TEST(CliTest, UnknownPreset) {
  const fs::path dir = TestDir();
  ExpectBadInput(dir, {"preset", "tweed"}, {"tweed"});
  ExpectBadInput(dir, {"preset", "tweed", "--out", (dir / "P.json").string()},
                 {"tweed"});
  ExpectBadInput(
      dir, {"synth", "--preset", "tweed", "--out", (dir / "T.csv").string()},
      {"tweed"});
}

TEST(CliTest, EvalRejectsTransmittanceQuantity) {
  const fs::path dir = DirWithInputs();
  ExpectBadInput(dir,
                 {"eval", "--params", (dir / "P.json").string(), "--dirs",
                  (dir / "D.csv").string(), "--out", (dir / "O.csv").string(),
                  "--quantity", "transmittance"},
                 {"quantity", "transmittance"});
}

TEST(CliTest, OutputInsideMissingDirectory) {
  const fs::path dir = DirWithInputs();
  const std::string out = (dir / "no_such_dir" / "O.csv").string();
  ExpectBadInput(dir,
                 {"eval", "--params", (dir / "P.json").string(), "--dirs",
                  (dir / "D.csv").string(), "--out", out},
                 {out});
  ExpectBadInput(dir,
                 {"synth", "--preset", "velvet", "--rows", "10", "--out", out},
                 {out});
  ExpectBadInput(dir, {"preset", "velvet", "--out", out}, {out});
  // Fits check their output before fitting (nothing printed, exit 2).
  const std::string data = (dir / "D.csv").string();
  ExpectBadInput(dir,
                 {"fit", "--model", "thread", "--data", data, "--out", out},
                 {out, "cannot write"});
  ExpectBadInput(dir,
                 {"fit", "--model", "lafortune", "--data", data, "--out",
                  (dir / "no_such_dir" / "L.exr").string()},
                 {"L.exr", "cannot write"});
  EXPECT_FALSE(fs::exists(dir / "no_such_dir"));
}

TEST(CliTest, SynthRejectsNegativeNoise) {
  const fs::path dir = TestDir();
  ExpectBadInput(dir,
                 {"synth", "--preset", "velvet", "--rows", "10", "--noise",
                  "-1", "--out", (dir / "T.csv").string()},
                 {"noise"});
}

TEST(CliTest, SynthRejectsZeroRows) {
  const fs::path dir = TestDir();
  ExpectBadInput(dir,
                 {"synth", "--preset", "velvet", "--rows", "0", "--out",
                  (dir / "T.csv").string()},
                 {"rows"});
}

// clothfit fit: a synthetic table from a thread file, fitted from the
// default start; the result file holds the recovered parameters and a
// "fit" object with standard deviations.
// RMS(model - data) / RMS(data) over the rows of two tables of the same
// directions.
double RelativeRms(const MeasurementTable& model,
                   const MeasurementTable& data) {
  double se = 0.0, ss = 0.0;
  for (size_t i = 0; i < model.rows.size(); ++i) {
    const glm::dvec3 d = model.rows[i].value - data.rows[i].value;
    se += glm::dot(d, d);
    ss += glm::dot(data.rows[i].value, data.rows[i].value);
  }
  return std::sqrt(se / ss);
}

fs::path DirWithThreadTable() {
  const fs::path dir = TestDir();
  WriteText(dir / "truth.json",
            "{\"model\": \"thread\", \"eta\": 1.5, \"kd\": 0.2, "
            "\"gamma_s_deg\": 6, \"gamma_v_deg\": 14, "
            "\"albedo\": [0.3, 0.2, 0.1]}");
  const RunResult synth =
      RunClothfit(dir, {"synth", "--params", (dir / "truth.json").string(),
                        "--rows", "1500", "--noise", "0.01", "--seed", "4",
                        "--out", (dir / "T.csv").string()});
  EXPECT_EQ(synth.status, 0) << Describe(synth);
  return dir;
}

// fit, by default (--energy-bound): a table drawn from a bounded thread (a
// parameter file with its energy_bound) is fitted by the bounded model, the
// written file carries its bound, and eval of that file reproduces the
// data the fit saw (1 % noise). --paper-model writes the paper's model (no
// bound). --energy-bound and --paper-model are refused for other models,
// and together.
TEST(CliTest, FitEnergyBoundWritesTheBoundedModelItFitted) {
  const fs::path dir = TestDir();
  ThreadParams truth;
  truth.eta = 1.5;
  truth.kd = 0.2;
  truth.gamma_s_deg = 6.0;
  truth.gamma_v_deg = 14.0;
  truth.albedo = glm::dvec3(0.3, 0.2, 0.1);
  truth.energy_bound = EnergyBoundOf(truth);
  ASSERT_NE(truth.energy_bound, nullptr);
  WriteParamFile(ParamFile{truth, ""}, (dir / "truth.json").string());
  const std::string data = (dir / "T.csv").string();
  ASSERT_EQ(RunClothfit(dir, {"synth", "--params",
                              (dir / "truth.json").string(), "--rows", "1500",
                              "--noise", "0.01", "--seed", "4", "--out", data})
                .status,
            0);
  const std::string out = (dir / "fit.json").string();
  const RunResult r = RunClothfit(
      dir, {"fit", "--model", "thread", "--data", data, "--out", out});
  ASSERT_EQ(r.status, 0) << Describe(r);
  EXPECT_NE(r.out.find("energy bound: lowers"), std::string::npos) << r.out;
  const ThreadParams fit = std::get<ThreadParams>(ReadParamFile(out).params);
  ASSERT_NE(fit.energy_bound, nullptr);
  EXPECT_NEAR(fit.eta, 1.5, 0.05 * 1.5);
  EXPECT_NEAR(fit.gamma_v_deg, 14.0, 0.05 * 14.0);
  const std::string evaluated = (dir / "E.csv").string();
  ASSERT_EQ(RunClothfit(dir, {"eval", "--params", out, "--dirs", data, "--out",
                              evaluated})
                .status,
            0);
  const MeasurementTable table = ReadTable(data).table;
  const MeasurementTable back = ReadTable(evaluated).table;
  ASSERT_EQ(back.rows.size(), table.rows.size());
  EXPECT_LT(RelativeRms(back, table), 0.02);
  ExpectBadInput(dir,
                 {"fit", "--model", "slab", "--data", data, "--energy-bound",
                  "--out", (dir / "slab.json").string()},
                 {"--energy-bound"});
  ExpectBadInput(dir,
                 {"fit", "--model", "lafortune", "--data", data,
                  "--paper-model", "--out", (dir / "l.json").string()},
                 {"--paper-model"});
  ExpectBadInput(dir,
                 {"fit", "--model", "thread", "--data", data, "--paper-model",
                  "--energy-bound", "--out", (dir / "t.json").string()},
                 {"--paper-model"});
  const std::string paper = (dir / "paper.json").string();
  const RunResult p = RunClothfit(dir, {"fit", "--model", "thread", "--data",
                                        data, "--paper-model", "--out", paper});
  ASSERT_LE(p.status, 1) << Describe(p);
  EXPECT_EQ(p.out.find("energy bound:"), std::string::npos) << p.out;
  EXPECT_EQ(std::get<ThreadParams>(ReadParamFile(paper).params).energy_bound,
            nullptr);
}

// synth draws the bounded model by default (--energy-bound; what fit fits
// by default): a preset's table is the bounded preset's values, below the
// paper's model (--paper-model) toward grazing (the linen's light side
// exceeds 1 there); a model other than thread or cloth is refused, and
// the two flags together.
TEST(CliTest, SynthEnergyBoundDrawsTheBoundedModel) {
  const fs::path dir = TestDir();
  const std::string plain = (dir / "D.csv").string();
  const std::string bounded = (dir / "B.csv").string();
  const std::string paper = (dir / "P.csv").string();
  for (const auto& [out, flag] :
       {std::pair<std::string, std::string>{plain, ""},
        {bounded, "--energy-bound"},
        {paper, "--paper-model"}}) {
    std::vector<std::string> args = {"synth",  "--preset", "linen_plain",
                                     "--rows", "400",      "--seed",
                                     "3",      "--out",    out};
    if (!flag.empty()) args.push_back(flag);
    const RunResult r = RunClothfit(dir, args);
    ASSERT_EQ(r.status, 0) << Describe(r);
  }
  ClothParams linen;
  ASSERT_TRUE(GetPreset("linen_plain", &linen));
  const ModelParams truth = WithEnergyBound(linen);
  const MeasurementTable d = ReadTable(plain).table;
  const MeasurementTable b = ReadTable(bounded).table;
  const MeasurementTable p = ReadTable(paper).table;
  ASSERT_EQ(b.rows.size(), p.rows.size());
  ASSERT_EQ(d.rows.size(), p.rows.size());
  int lower = 0;
  for (size_t i = 0; i < b.rows.size(); ++i) {
    const glm::dvec3 want =
        Evaluate(truth, b.rows[i].wi, b.rows[i].wo, b.quantity);
    const glm::dvec3 want_paper =
        Evaluate(ModelParams(linen), p.rows[i].wi, p.rows[i].wo, p.quantity);
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(b.rows[i].value[c], want[c], 1e-9 * (1.0 + want[c])) << i;
      EXPECT_EQ(d.rows[i].value[c], b.rows[i].value[c]) << i;
      EXPECT_NEAR(p.rows[i].value[c], want_paper[c],
                  1e-9 * (1.0 + want_paper[c]))
          << i;
    }
    EXPECT_LE(b.rows[i].value.x, p.rows[i].value.x * (1.0 + 1e-9)) << i;
    if (b.rows[i].value.x < 0.99 * p.rows[i].value.x) ++lower;
  }
  EXPECT_GT(lower, 0);
  ExpectBadInput(dir,
                 {"synth", "--preset", "linen_plain", "--energy-bound",
                  "--paper-model", "--out", (dir / "X.csv").string()},
                 {"--paper-model"});
  WriteParamFile(ParamFile{SlabParams(), ""}, (dir / "slab.json").string());
  ExpectBadInput(dir,
                 {"synth", "--params", (dir / "slab.json").string(),
                  "--energy-bound", "--out", (dir / "S.csv").string()},
                 {"--energy-bound"});
}

TEST(CliTest, FitThreadRecoversParametersAndWritesFitObject) {
  const fs::path dir = DirWithThreadTable();
  const RunResult r = RunClothfit(
      dir, {"fit", "--model", "thread", "--data", (dir / "T.csv").string(),
            "--out", (dir / "fit.json").string()});
  ASSERT_EQ(r.status, 0) << Describe(r);
  EXPECT_NE(r.out.find("gamma_s_deg"), std::string::npos);  // the summary
  const ParamFile fit = ReadParamFile((dir / "fit.json").string());
  const ThreadParams& p = std::get<ThreadParams>(fit.params);
  EXPECT_NEAR(p.eta, 1.5, 0.05 * 1.5);
  EXPECT_NEAR(p.kd, 0.2, 0.05);
  EXPECT_NEAR(p.gamma_s_deg, 6.0, 0.05 * 6.0);
  EXPECT_NEAR(p.gamma_v_deg, 14.0, 0.05 * 14.0);
  EXPECT_NEAR(p.albedo.x, 0.3, 0.03 * 0.3);
  for (const char* key : {"\"stddev\"", "\"relative_rms\"", "\"iterations\"",
                          "\"termination\"", "\"gamma_s_deg\""}) {
    EXPECT_NE(fit.fit_json.find(key), std::string::npos) << key;
  }
  // The wall time is in the summary, not the file (determinism).
  EXPECT_EQ(fit.fit_json.find("seconds"), std::string::npos);
  EXPECT_EQ(fit.fit_json.find("nan"), std::string::npos);
}

TEST(CliTest, FitClothFromPresetWeaveWithToleranceReportsCandidates) {
  const fs::path dir = TestDir();
  ASSERT_EQ(
      RunClothfit(dir, {"synth", "--preset", "linen_plain", "--rows", "1000",
                        "--noise", "0.02", "--out", (dir / "T.csv").string()})
          .status,
      0);
  const RunResult r = RunClothfit(
      dir, {"fit", "--model", "cloth", "--data", (dir / "T.csv").string(),
            "--preset", "linen_plain", "--generic-start", "--tolerance", "0.05",
            "--out", (dir / "fit.json").string()});
  ASSERT_EQ(r.status, 0) << Describe(r);
  EXPECT_NE(r.out.find("model selection"), std::string::npos);
  const ParamFile fit = ReadParamFile((dir / "fit.json").string());
  EXPECT_TRUE(std::holds_alternative<ClothParams>(fit.params));
  EXPECT_NE(fit.fit_json.find("\"selection\""), std::string::npos);
  EXPECT_NE(fit.fit_json.find("\"bic\""), std::string::npos);
}

TEST(CliTest, FitThatDoesNotConvergeExitsOne) {
  const fs::path dir = DirWithThreadTable();
  const RunResult r = RunClothfit(
      dir, {"fit", "--model", "thread", "--data", (dir / "T.csv").string(),
            "--max-iterations", "1", "--out", (dir / "fit.json").string()});
  EXPECT_EQ(r.status, 1) << Describe(r);
  EXPECT_NE(r.err.find("the fit did not converge"), std::string::npos) << r.err;
}

TEST(CliTest, FitBadUsage) {
  const fs::path dir = DirWithThreadTable();
  const std::string data = (dir / "T.csv").string();
  const std::string out = (dir / "fit.json").string();
  ExpectBadInput(dir, {"fit", "--model", "lobes", "--data", data, "--out", out},
                 {"--model", "lobes"});
  ExpectBadInput(dir, {"fit", "--model", "cloth", "--data", data, "--out", out},
                 {"--init", "--preset"});
  ExpectBadInput(dir,
                 {"fit", "--model", "thread", "--data", data, "--fix",
                  "roughness", "--out", out},
                 {"roughness"});
  ExpectBadInput(dir,
                 {"fit", "--model", "thread", "--data",
                  (dir / "missing.csv").string(), "--out", out},
                 {"missing.csv"});
  ExpectBadInput(dir,
                 {"fit", "--model", "thread", "--data", data, "--loss", "l1",
                  "--out", out},
                 {"--loss"});
  ExpectBadInput(dir,
                 {"fit", "--model", "thread", "--data", data, "--noise",
                  "gaussian", "--out", out},
                 {"--noise", "gaussian"});
  ExpectBadInput(dir,
                 {"fit", "--model", "thread", "--data", data, "--noise-level",
                  "-0.01", "--out", out},
                 {"--noise-level"});
  ExpectBadInput(dir,
                 {"fit", "--model", "thread", "--data", data, "--noise",
                  "absolute", "--noise-floor", "0.1", "--out", out},
                 {"--noise-floor"});
}

// Data on an arbitrary scale: --fit-scale finds the factor, the parameter
// file keeps it, and eval of the file reproduces the data the fit saw
// (plot, render and the renderer API evaluate the same way).
TEST(CliTest, FitScaleIsKeptAndEvalReproducesTheScaledData) {
  const fs::path dir = TestDir();
  const std::string clean = (dir / "T.csv").string();
  ASSERT_EQ(RunClothfit(dir, {"synth", "--preset", "linen_plain", "--rows",
                              "800", "--noise", "0.01", "--out", clean})
                .status,
            0);
  MeasurementTable table = ReadTable(clean).table;
  for (TableRow& row : table.rows) {
    row.value *= 0.3;
    row.sigma *= 0.3;
  }
  const std::string scaled = (dir / "scaled.csv").string();
  WriteTable(table, scaled);
  const std::string out = (dir / "fit.json").string();
  const RunResult fit =
      RunClothfit(dir, {"fit", "--model", "cloth", "--preset", "linen_plain",
                        "--data", scaled, "--fit-scale", "--out", out});
  ASSERT_EQ(fit.status, 0) << Describe(fit);
  const ParamFile file = ReadParamFile(out);
  const ClothParams& c = std::get<ClothParams>(file.params);
  EXPECT_NEAR(c.scale, 0.3, 0.3 * 0.02);
  EXPECT_NE(ReadText(out).find("\"scale\""), std::string::npos);

  const std::string evaluated = (dir / "E.csv").string();
  const RunResult eval = RunClothfit(
      dir, {"eval", "--params", out, "--dirs", scaled, "--out", evaluated});
  ASSERT_EQ(eval.status, 0) << Describe(eval);
  const MeasurementTable back = ReadTable(evaluated).table;
  ASSERT_EQ(back.rows.size(), table.rows.size());
  // The data's own noise is 1 %; 0.3's eval was 3.3x off.
  EXPECT_LT(RelativeRms(back, table), 0.03);
}

// A table without a sigma column is fitted with relative noise of an
// estimated level, and the fit object says so; the level comes out near
// the table's (1 %); --noise table on such a table is bad input naming
// it; a given level is used as it is.
TEST(CliTest, FitWithoutSigmaUsesRelativeNoiseAndReportsItsLevel) {
  const fs::path dir = DirWithThreadTable();
  MeasurementTable table = ReadTable((dir / "T.csv").string()).table;
  ASSERT_TRUE(table.has_sigma);
  table.has_sigma = false;
  const std::string data = (dir / "nosigma.csv").string();
  WriteTable(table, data);
  const std::string out = (dir / "fit.json").string();
  const RunResult r = RunClothfit(
      dir, {"fit", "--model", "thread", "--data", data, "--out", out});
  ASSERT_EQ(r.status, 0) << Describe(r);
  EXPECT_NE(r.out.find("noise: relative"), std::string::npos) << r.out;
  nlohmann::json fit = nlohmann::json::parse(ReadText(out))["fit"];
  EXPECT_EQ(fit["noise"]["model"], "relative");
  EXPECT_TRUE(fit["noise"]["level_estimated"].get<bool>());
  EXPECT_NEAR(fit["noise"]["level"].get<double>(), 0.01, 0.001);
  EXPECT_TRUE(fit.contains("stddev_sandwich"));
  EXPECT_GT(fit["stddev"]["kd"].get<double>(), 0.0);

  ExpectBadInput(dir,
                 {"fit", "--model", "thread", "--data", data, "--noise",
                  "table", "--out", out},
                 {"nosigma.csv", "sigma"});

  const RunResult given =
      RunClothfit(dir, {"fit", "--model", "thread", "--data", data,
                        "--noise-level", "0.01", "--out", out});
  ASSERT_EQ(given.status, 0) << Describe(given);
  fit = nlohmann::json::parse(ReadText(out))["fit"];
  EXPECT_FALSE(fit["noise"]["level_estimated"].get<bool>());
  EXPECT_EQ(fit["noise"]["level"].get<double>(), 0.01);
  EXPECT_FALSE(fit.contains("stddev_sandwich"));
}

// Tables that leave a fit nothing to fit are bad input (exit 2) for every
// fit command; a one-row table cannot determine the model: exit 1.
TEST(CliTest, FitWithoutInformationIsRefusedOrNotConverged) {
  const fs::path dir = TestDir();
  const std::string h =
      "# quantity: brdf\ntheta_i,phi_i,theta_o,phi_o,r,g,b,weight\n";
  WriteText(dir / "zero.csv",
            h + "30,0,40,180,0.1,0.1,0.1,0\n50,90,20,0,0.2,0.2,0.2,0\n");
  WriteText(dir / "bad.csv", h + "30,0,40,180,x,0.1,0.1,1\n");
  WriteText(dir / "one.csv", h + "30,0,40,180,0.1,0.1,0.1,1\n");
  const std::string out = (dir / "fit.json").string();
  for (const std::vector<std::string>& model :
       {std::vector<std::string>{"--model", "thread"},
        {"--model", "cloth", "--preset", "linen_plain"},
        {"--model", "slab"},
        {"--model", "lafortune", "--lobes", "1"}}) {
    std::vector<std::string> args = {"fit"};
    args.insert(args.end(), model.begin(), model.end());
    std::vector<std::string> zero = args;
    zero.insert(zero.end(),
                {"--data", (dir / "zero.csv").string(), "--out", out});
    ExpectBadInput(dir, zero, {"zero.csv", "weight 0", "nothing to fit"});
    std::vector<std::string> bad = args;
    bad.insert(bad.end(), {"--data", (dir / "bad.csv").string(),
                           "--skip-invalid", "--out", out});
    ExpectBadInput(dir, bad, {"bad.csv", "no rows", "invalid"});
  }
  const RunResult one =
      RunClothfit(dir, {"fit", "--model", "thread", "--data",
                        (dir / "one.csv").string(), "--out", out});
  EXPECT_EQ(one.status, 1) << Describe(one);
  EXPECT_NE(one.err.find("cannot determine"), std::string::npos) << one.err;
}

// The cloth model is reflection only: transmission rows are left out with
// a warning and counted in the "fit" object; only such rows: exit 2.
TEST(CliTest, ClothFitLeavesOutTransmissionRowsAndSaysSo) {
  const fs::path dir = TestDir();
  const std::string table = (dir / "T.csv").string();
  ASSERT_EQ(RunClothfit(dir, {"synth", "--preset", "linen_plain", "--rows",
                              "300", "--out", table})
                .status,
            0);
  WriteText(dir / "mixed.csv",
            ReadText(dir / "T.csv") + "30,0,120,0,0.5,0.5,0.5\n");
  const RunResult r =
      RunClothfit(dir, {"fit", "--model", "cloth", "--preset", "linen_plain",
                        "--data", (dir / "mixed.csv").string(), "--out",
                        (dir / "fit.json").string()});
  ASSERT_EQ(r.status, 0) << Describe(r);
  EXPECT_NE(r.err.find("warning: 1 row(s) are not reflection"),
            std::string::npos)
      << r.err;
  const ParamFile fit = ReadParamFile((dir / "fit.json").string());
  EXPECT_NE(fit.fit_json.find("\"rows_not_used\":1"), std::string::npos)
      << fit.fit_json;
  EXPECT_NE(fit.fit_json.find("\"residuals\":900"), std::string::npos)
      << fit.fit_json;
  WriteText(dir / "below.csv",
            "# quantity: brdf\ntheta_i,phi_i,theta_o,phi_o,r,g,b\n"
            "30,0,120,0,0.5,0.5,0.5\n");
  ExpectBadInput(
      dir,
      {"fit", "--model", "cloth", "--preset", "linen_plain", "--data",
       (dir / "below.csv").string(), "--out", (dir / "f.json").string()},
      {"below.csv", "reflection only"});
}

// Lafortune: a virtual-gonioreflectometer table -> per-texel and mip-level
// fits -> an EXR parameter mip map with its index; and one model for a
// table without texels, evaluated by `clothfit eval`.
TEST(CliTest, LafortuneFromVirtualGonioWritesParameterMipmap) {
  const fs::path dir = TestDir();
  const std::string table = (dir / "g.csv").string();
  const RunResult synth =
      RunClothfit(dir, {"synth", "--gonio", "plain", "--texels", "2",
                        "--directions", "3", "--out", table});
  ASSERT_EQ(synth.status, 0) << Describe(synth);
  const std::string exr = (dir / "g.exr").string();
  const RunResult fit = RunClothfit(
      dir, {"fit", "--model", "lafortune", "--data", table, "--lobes", "1",
            "--mip", "--threads", "2", "--out", exr});
  ASSERT_TRUE(WroteTextureMap(fit)) << Describe(fit);
  EXPECT_NE(fit.out.find("level 1: 1x1"), std::string::npos) << fit.out;
  const ParamMipmap m = ReadParamMipmap(exr);
  ASSERT_EQ(m.levels.size(), 2u);
  EXPECT_EQ(m.levels[0].width, 2);
  EXPECT_NE(std::find(m.channels.begin(), m.channels.end(), "lobe0.N.G"),
            m.channels.end());
  EXPECT_NE(std::find(m.channels.begin(), m.channels.end(), "lut.8.A"),
            m.channels.end());  // 3 x 3 views
}

// The same through an image stack: synth --gonio --stack writes one EXR
// per (light, view) pair and a manifest; fit --stack reads them back.
// clothfit bench --quick: seconds; its CSV parses (a row per configuration
// with finite times and errors, one default per model), the charts and the
// summary are written.
TEST(CliTest, BenchQuickWritesCsvChartsAndSummary) {
  const fs::path dir = TestDir();
  const std::string out = (dir / "bench").string();
  const RunResult r =
      RunClothfit(dir, {"bench", "--quick", "--repeats", "2", "--out", out});
  ASSERT_EQ(r.status, 0) << Describe(r);
  std::ifstream csv(out + "/bench.csv");
  std::string line;
  ASSERT_TRUE(std::getline(csv, line));
  EXPECT_EQ(line.rfind("model,config,default,repeats,wall_median_s", 0), 0u);
  std::map<std::string, int> rows, defaults;
  while (std::getline(csv, line)) {
    // model,"config",default,repeats,wall median,min,max,cpu,peak,value
    // error,param error,size,success
    const size_t q1 = line.find('"'), q2 = line.find('"', q1 + 1);
    ASSERT_NE(q2, std::string::npos) << line;
    const std::string model = line.substr(0, q1 - 1);
    std::stringstream rest(line.substr(q2 + 2));
    std::vector<double> v;
    std::string field;
    while (std::getline(rest, field, ',')) {
      EXPECT_EQ(field.find("nan"), std::string::npos) << line;
      v.push_back(field.empty() ? std::nan("") : std::stod(field));  // n/a
    }
    ASSERT_EQ(v.size(), 11u) << line;
    ++rows[model];
    defaults[model] += v[0] == 1.0;
    EXPECT_EQ(v[1], 2.0) << line;                             // repeats
    EXPECT_GT(v[2], 0.0) << line;                             // wall median
    EXPECT_LE(v[3], v[2]);                                    // min <= median
    EXPECT_GE(v[4], v[2]);                                    // max >= median
    EXPECT_TRUE(std::isfinite(v[7]) && v[7] >= 0.0) << line;  // error
  }
  for (const char* model : {"thread", "cloth", "lafortune", "slab", "holes"}) {
    EXPECT_GE(rows[model], 2) << model;
    EXPECT_EQ(defaults[model], 1) << model;
    EXPECT_GT(fs::file_size(out + "/" + model + "_speed_accuracy.png"), 1000u);
  }
  EXPECT_GT(fs::file_size(out + "/lafortune_size.png"), 1000u);
  const std::string summary = ReadFileToString(out + "/summary.md");
  EXPECT_NE(summary.find("(default)"), std::string::npos);
  EXPECT_NE(summary.find("--tolerance"), std::string::npos);
  // The SciPy peer: side by side where Debian's python3-scipy is installed
  // (scripts/setup.sh installs it), else skipped with a message.
  const bool scipy =
      std::system("/usr/bin/python3 -c 'import scipy' 2>/dev/null") == 0;
  if (scipy) {
    EXPECT_NE(summary.find("SciPy peer, lobes=2 without lookup table"),
              std::string::npos)
        << summary;
    EXPECT_NE(ReadFileToString(out + "/bench.csv")
                  .find("\"scipy least_squares lobes=2 lut=off\""),
              std::string::npos);
  } else {
    EXPECT_NE(summary.find("SciPy peer skipped"), std::string::npos) << summary;
  }
  ExpectBadInput(dir, {"bench", "--quick", "--models", "teapot", "--out", out},
                 {"teapot"});
  // Without a usable Python the peer is skipped with a message, not an
  // error.
  const std::string no_peer = (dir / "no_peer").string();
  const RunResult skipped = RunClothfit(
      dir, {"bench", "--quick", "--repeats", "1", "--models", "lafortune",
            "--python", (dir / "no_python").string(), "--out", no_peer});
  ASSERT_EQ(skipped.status, 0) << Describe(skipped);
  EXPECT_NE(skipped.err.find("SciPy peer skipped"), std::string::npos)
      << skipped.err;
  EXPECT_NE(
      ReadFileToString(no_peer + "/summary.md").find("SciPy peer skipped"),
      std::string::npos);
}

// bench --stability --quick: success rates per knob level; the thread fit
// without a robust loss must fail on 20 % gross outliers and succeed with
// the Cauchy loss (the failure mode docs/bench.md names).
TEST(CliTest, BenchStabilityQuickWritesRatesAndCharts) {
  const fs::path dir = TestDir();
  const std::string out = (dir / "stability").string();
  const RunResult r =
      RunClothfit(dir, {"bench", "--quick", "--stability", "--out", out});
  ASSERT_EQ(r.status, 0) << Describe(r);
  std::ifstream csv(out + "/stability.csv");
  std::string line;
  ASSERT_TRUE(std::getline(csv, line));
  EXPECT_EQ(line, "fitter,knob,level,level_label,runs,successes,median_error");
  std::map<std::string, std::pair<int, int>> at_20_percent_outliers;
  int rows = 0;
  while (std::getline(csv, line)) {
    ++rows;
    std::stringstream fields(line);
    std::string fitter, knob, level, label, runs, successes;
    std::getline(fields, fitter, ',');
    std::getline(fields, knob, ',');
    std::getline(fields, level, ',');
    std::getline(fields, label, ',');
    std::getline(fields, runs, ',');
    std::getline(fields, successes, ',');
    EXPECT_LE(std::stoi(successes), std::stoi(runs)) << line;
    if (knob == "outliers" && std::stod(level) == 0.2) {
      at_20_percent_outliers[fitter] = {std::stoi(successes), std::stoi(runs)};
    }
  }
  EXPECT_GE(rows, 15);
  EXPECT_EQ(at_20_percent_outliers["thread"].first, 0);
  EXPECT_EQ(at_20_percent_outliers["thread+cauchy"].first,
            at_20_percent_outliers["thread+cauchy"].second);
  for (const char* knob : {"noise", "start_distance", "coverage", "outliers"}) {
    EXPECT_GT(fs::file_size(out + "/stability_" + std::string(knob) + ".png"),
              1000u);
  }
}

TEST(CliTest, PlotDrawsModelAgainstMeasuredRows) {
  const fs::path dir = TestDir();
  const std::string table = (dir / "t.csv").string();
  ASSERT_EQ(RunClothfit(dir, {"synth", "--preset", "velvet", "--rows", "3000",
                              "--out", table})
                .status,
            0);
  const std::string png = (dir / "p.png").string();
  const RunResult r = RunClothfit(
      dir, {"plot", "--preset", "velvet", "--data", table, "--incidence-deg",
            "10,50", "--window-deg", "15", "--out", png});
  ASSERT_EQ(r.status, 0) << Describe(r);
  EXPECT_GT(fs::file_size(png), 2000u);
  ExpectBadInput(dir,
                 {"plot", "--preset", "velvet", "--data", table,
                  "--incidence-deg", "95", "--out", png},
                 {"--incidence-deg", "95"});
}

// Nothing lost: a fit killed mid-way leaves an earlier output
// untouched and no temporary file behind (outputs are written to a
// temporary name and renamed only when complete).
TEST(CliTest, KilledFitLeavesEarlierOutputUntouched) {
  const fs::path dir = TestDir();
  const std::string table = (dir / "g.csv").string();
  ASSERT_EQ(RunClothfit(dir, {"synth", "--gonio", "plain", "--texels", "4",
                              "--directions", "8", "--out", table})
                .status,
            0);
  const fs::path out = dir / "P.exr";
  WriteText(out, "earlier result");
  WriteText(dir / "P.exr.json", "earlier index");
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    const int null = open("/dev/null", O_WRONLY);
    dup2(null, 1);
    dup2(null, 2);
    execl(CLOTHFIT_BINARY, CLOTHFIT_BINARY, "fit", "--model", "lafortune",
          "--data", table.c_str(), "--lobes", "3", "--mip", "--threads", "1",
          "--out", out.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  usleep(500 * 1000);  // reading the table and fitting take seconds
  ASSERT_EQ(kill(pid, SIGKILL), 0);
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFSIGNALED(status)) << "the fit ended before it was killed";
  EXPECT_EQ(ReadText(out), "earlier result");
  EXPECT_EQ(ReadText(dir / "P.exr.json"), "earlier index");
  for (const auto& entry : fs::directory_iterator(dir)) {
    EXPECT_EQ(entry.path().filename().string().find(".tmp."), std::string::npos)
        << entry.path();
  }
}

TEST(CliTest, LafortuneFromImageStack) {
  const fs::path dir = TestDir();
  const std::string manifest = (dir / "stack.csv").string();
  const RunResult synth =
      RunClothfit(dir, {"synth", "--gonio", "satin", "--texels", "2",
                        "--directions", "2", "--stack", manifest});
  ASSERT_EQ(synth.status, 0) << Describe(synth);
  EXPECT_TRUE(fs::exists(dir / "stack_0000.exr"));
  EXPECT_TRUE(fs::exists(dir / "stack_0015.exr"));  // 4 lights x 4 views
  const std::string exr = (dir / "s.exr").string();
  const RunResult fit =
      RunClothfit(dir, {"fit", "--model", "lafortune", "--stack", manifest,
                        "--lobes", "1", "--out", exr});
  ASSERT_TRUE(WroteTextureMap(fit)) << Describe(fit);
  const ParamMipmap m = ReadParamMipmap(exr);
  ASSERT_EQ(m.levels.size(), 1u);  // no --mip: level 0 only
  EXPECT_EQ(m.levels[0].width, 2);
  EXPECT_EQ(m.levels[0].height, 2);

  // The stack carries the texels' normals (its normal map): the fit holds
  // the same per-texel frames as a fit of the same gonio's table.
  EXPECT_TRUE(fs::exists(dir / "stack_normal.exr"));
  const std::string table = (dir / "t.csv").string();
  ASSERT_EQ(RunClothfit(dir, {"synth", "--gonio", "satin", "--texels", "2",
                              "--directions", "2", "--out", table})
                .status,
            0);
  const std::string from_table = (dir / "t.exr").string();
  ASSERT_TRUE(WroteTextureMap(
      RunClothfit(dir, {"fit", "--model", "lafortune", "--data", table,
                        "--lobes", "1", "--out", from_table})));
  const ParamMipmap t = ReadParamMipmap(from_table);
  ASSERT_EQ(t.channels, m.channels);
  double tilt = 0.0;
  for (const char* axis : {"normal.X", "normal.Y", "normal.Z"}) {
    const size_t c = static_cast<size_t>(
        std::find(m.channels.begin(), m.channels.end(), axis) -
        m.channels.begin());
    ASSERT_LT(c, m.channels.size()) << axis;
    for (size_t i = 0; i < 4; ++i) {
      EXPECT_NEAR(m.levels[0].data[c][i], t.levels[0].data[c][i], 1e-6)
          << axis << " texel " << i;
      if (axis[7] != 'Z') tilt += std::abs(t.levels[0].data[c][i]);
    }
  }
  EXPECT_GT(tilt, 1e-3);  // the gonio's normals are not all +z
}

TEST(CliTest, LafortuneSingleTableFitThenEval) {
  const fs::path dir = TestDir();
  // A Lafortune model written by hand, sampled by synth, fitted back.
  WriteText(dir / "truth.json",
            "{\"model\": \"lafortune\", \"diffuse\": [0.1, 0.07, 0.04], "
            "\"lobes\": [{\"Cx\": [-0.9, -0.9, -0.9], \"Cy\": [-0.8, -0.8, "
            "-0.8], \"Cz\": [0.9, 0.9, 0.9], \"N\": [8, 10, 12]}]}");
  const std::string table = (dir / "t.csv").string();
  ASSERT_EQ(RunClothfit(dir, {"synth", "--params",
                              (dir / "truth.json").string(), "--rows", "800",
                              "--quantity", "cosine_weighted", "--out", table})
                .status,
            0);
  const std::string out = (dir / "fit.json").string();
  const RunResult fit =
      RunClothfit(dir, {"fit", "--model", "lafortune", "--data", table,
                        "--lobes", "1", "--no-lut", "--out", out});
  ASSERT_EQ(fit.status, 0) << Describe(fit);
  const ParamFile p = ReadParamFile(out);
  const LafortuneModel& m = std::get<LafortuneModel>(p.params);
  EXPECT_NEAR(m.params.diffuse.x, 0.1, 0.005);
  EXPECT_NE(p.fit_json.find("relative_rms"), std::string::npos);
  const RunResult eval =
      RunClothfit(dir, {"eval", "--params", out, "--dirs", table, "--quantity",
                        "cosine_weighted", "--out", (dir / "e.csv").string()});
  EXPECT_EQ(eval.status, 0) << Describe(eval);
  // Output kinds must match the table: texels -> .exr, none -> .json.
  ExpectBadInput(dir,
                 {"fit", "--model", "lafortune", "--data", table, "--out",
                  (dir / "x.exr").string()},
                 {".json"});
  ExpectBadInput(dir,
                 {"fit", "--model", "lafortune", "--data", table, "--lobes",
                  "5", "--out", out},
                 {"--lobes"});

  // The "fit" object (docs/formats.md): cost, termination, convergence.
  for (const char* key :
       {"\"final_cost\"", "\"termination\"", "\"converged\":true"}) {
    EXPECT_NE(p.fit_json.find(key), std::string::npos) << key;
  }
  // --init: a fit started from the result needs fewer iterations; its lobe
  // count is the default; a different --lobes or another model is refused.
  const std::string again = (dir / "again.json").string();
  const RunResult init =
      RunClothfit(dir, {"fit", "--model", "lafortune", "--data", table,
                        "--init", out, "--no-lut", "--out", again});
  ASSERT_EQ(init.status, 0) << Describe(init);
  const ParamFile q = ReadParamFile(again);
  EXPECT_EQ(std::get<LafortuneModel>(q.params).params.lobes.size(), 1u);
  const auto iterations = [](const ParamFile& f) {
    return nlohmann::json::parse(f.fit_json)["iterations"].get<int>();
  };
  EXPECT_LT(iterations(q), iterations(p)) << q.fit_json << "\n" << p.fit_json;
  EXPECT_NEAR(std::get<LafortuneModel>(q.params).params.diffuse.x, 0.1, 0.005);
  ExpectBadInput(dir,
                 {"fit", "--model", "lafortune", "--data", table, "--init", out,
                  "--lobes", "2", "--out", again},
                 {"--lobes", "has 1"});
  WriteText(dir / "slab.json",
            R"({"model": "slab", "tau": 0.5, "albedo": [0.9, 0.8, 0.7]})");
  ExpectBadInput(dir,
                 {"fit", "--model", "lafortune", "--data", table, "--init",
                  (dir / "slab.json").string(), "--out", again},
                 {"slab.json", "lafortune"});
  // Random directions give one row per view: no view has enough samples
  // for a lookup-table entry, which the summary says.
  const RunResult sparse = RunClothfit(
      dir, {"fit", "--model", "lafortune", "--data", table, "--out", again});
  EXPECT_EQ(sparse.status, 0) << Describe(sparse);
  EXPECT_NE(sparse.err.find("0 of 800 views have at least 16 samples"),
            std::string::npos)
      << sparse.err;
  // A gonio-style table (each of 18 lights at each of 6 views): a lookup
  // table never fitted (one alternation) is not converged, exit 1.
  std::string grid =
      "# quantity: cosine_weighted\ntheta_i,phi_i,theta_o,phi_o\n";
  for (int v = 0; v < 6; ++v) {
    for (int l = 0; l < 18; ++l) {
      grid += std::to_string(10 * (l % 6) + 5) + "," +
              std::to_string(60 * (l / 6) + 15) + "," +
              std::to_string(12 * v + 5) + "," + std::to_string(45 * v) + "\n";
    }
  }
  WriteText(dir / "grid_dirs.csv", grid);
  const std::string grid_table = (dir / "grid.csv").string();
  ASSERT_EQ(RunClothfit(dir, {"eval", "--params", out, "--dirs",
                              (dir / "grid_dirs.csv").string(), "--quantity",
                              "cosine_weighted", "--out", grid_table})
                .status,
            0);
  const RunResult capped =
      RunClothfit(dir, {"fit", "--model", "lafortune", "--data", grid_table,
                        "--alternations", "1", "--out", again});
  EXPECT_EQ(capped.status, 1) << Describe(capped);
  EXPECT_NE(capped.err.find("the fit did not converge"), std::string::npos)
      << capped.err;
}

// The texel (x, y) of level l of the mip map below: its diffuse rho_d and
// whether it has the lobe (Cx, Cy, Cz, N) = (-0.5, -0.75, 1, 3). Every
// value is exact in float (the EXR stores FLOAT channels).
glm::dvec3 MipDiffuse(int l, int x, int y) {
  return glm::dvec3(0.125 * (1 + x + 4 * y), 0.0625 * (1 + l), 0.5);
}
bool MipHasLobe(int l, int x, int y) { return (l + x + y) % 2 == 1; }

// A Lafortune parameter mip map with a 4 x 2 base (levels 4 x 2, 2 x 1,
// 1 x 1, OpenEXR's ROUND_DOWN sizes), no lookup tables, normals +z.
void WriteTestMip(const std::string& path) {
  LafortuneMipResult r;
  const int sizes[3][2] = {{4, 2}, {2, 1}, {1, 1}};
  for (int l = 0; l < 3; ++l) {
    LafortuneLevel level;
    level.width = sizes[l][0];
    level.height = sizes[l][1];
    for (int y = 0; y < level.height; ++y) {
      for (int x = 0; x < level.width; ++x) {
        LafortuneFitResult t;
        t.params.params.diffuse = MipDiffuse(l, x, y);
        if (MipHasLobe(l, x, y)) {
          LafortuneLobe lobe;
          lobe.cx = glm::dvec3(-0.5);
          lobe.cy = glm::dvec3(-0.75);
          lobe.cz = glm::dvec3(1.0);
          lobe.n = glm::dvec3(3.0);
          t.params.params.lobes.push_back(lobe);
        }
        level.texels.push_back(t);
      }
    }
    r.levels.push_back(level);
  }
  WriteParamMipmap(ToParamMipmap(r), path);
}

// docs/models.md for texel (x, y) of level l, in the surface frame (normal +z,
// no lookup table): rho = l.z (rho_d + [Cx lx vx + Cy ly vy + Cz lz vz]^N),
// [a]^N = 0 for a <= 0; the BRDF f = rho / l.z.
glm::dvec3 MipExpected(int l, int x, int y, const glm::dvec3& wi,
                       const glm::dvec3& wo, Quantity q) {
  double lobe = 0.0;
  if (MipHasLobe(l, x, y)) {
    const double a = -0.5 * wi.x * wo.x - 0.75 * wi.y * wo.y + wi.z * wo.z;
    lobe = a > 0.0 ? a * a * a : 0.0;
  }
  const glm::dvec3 f = MipDiffuse(l, x, y) + glm::dvec3(lobe);
  return q == Quantity::kBrdf ? f : f * wi.z;
}

TEST(CliTest, EvalParameterMipmapAtTexels) {
  const fs::path dir = TestDir();
  const std::string exr = (dir / "P.exr").string();
  WriteTestMip(exr);
  const std::pair<glm::dvec3, glm::dvec3> pairs[] = {
      {glm::normalize(glm::dvec3(0.3, 0.2, 0.9)),
       glm::normalize(glm::dvec3(-0.35, -0.1, 0.8))},  // near the mirror
      {glm::normalize(glm::dvec3(-0.6, 0.1, 0.5)),
       glm::normalize(glm::dvec3(0.1, 0.7, 0.6))}};
  const int sizes[3][2] = {{4, 2}, {2, 1}, {1, 1}};
  for (int level = 0; level < 3; ++level) {
    MeasurementTable table;
    table.direction_columns = DirectionColumns::kVectors;
    table.has_texels = true;
    for (int y = 0; y < sizes[level][1]; ++y) {
      for (int x = 0; x < sizes[level][0]; ++x) {
        for (const auto& [wi, wo] : pairs) {
          TableRow row;
          row.wi = wi;
          row.wo = wo;
          row.s = x;
          row.t = y;
          table.rows.push_back(row);
        }
      }
    }
    const std::string dirs = (dir / "D.csv").string();
    WriteTable(table, dirs);
    ReadTableOptions read_options;
    read_options.values_optional = true;
    const MeasurementTable in = ReadTable(dirs, read_options).table;
    for (Quantity q : {Quantity::kBrdf, Quantity::kCosineWeighted}) {
      const std::string out = (dir / "O.csv").string();
      std::vector<std::string> args = {"eval",   "--params",   exr,
                                       "--dirs", dirs,         "--out",
                                       out,      "--quantity", QuantityName(q)};
      if (level > 0) {
        args.push_back("--level");
        args.push_back(std::to_string(level));
      }
      const RunResult r = RunClothfit(dir, args);
      ASSERT_EQ(r.status, 0) << Describe(r);
      EXPECT_EQ(r.err, "");
      const MeasurementTable got = ReadTable(out).table;
      EXPECT_EQ(got.quantity, q);
      EXPECT_TRUE(got.has_texels);
      ASSERT_EQ(got.rows.size(), in.rows.size());
      for (size_t i = 0; i < got.rows.size(); ++i) {
        const TableRow& row = in.rows[i];
        EXPECT_EQ(got.rows[i].s, row.s);
        EXPECT_EQ(got.rows[i].t, row.t);
        ExpectRelativelyNear(
            got.rows[i].value,
            MipExpected(level, row.s, row.t, row.wi, row.wo, q), 1e-12,
            "level " + std::to_string(level) + " " + QuantityName(q) + " row " +
                std::to_string(i));
      }
    }
  }
}

TEST(CliTest, EvalParameterMipmapBadInput) {
  const fs::path dir = TestDir();
  const std::string exr = (dir / "P.exr").string();
  WriteTestMip(exr);
  const std::string out = (dir / "O.csv").string();
  const std::string no_texels = (dir / "no_texels.csv").string();
  WriteText(no_texels,
            "# clothfit-table 1\n"
            "theta_i,phi_i,theta_o,phi_o\n"
            "10,0,20,180\n");
  ExpectBadInput(dir,
                 {"eval", "--params", exr, "--dirs", no_texels, "--out", out},
                 {no_texels, "s,t"});
  // Level 0 is 4 x 2 texels, level 1 2 x 1.
  const std::string texels = (dir / "texels.csv").string();
  WriteText(texels,
            "# clothfit-table 1\n"
            "theta_i,phi_i,theta_o,phi_o,s,t\n"
            "10,0,20,180,3,1\n"
            "10,0,20,180,2,0\n");
  const RunResult good = RunClothfit(
      dir, {"eval", "--params", exr, "--dirs", texels, "--out", out});
  ASSERT_EQ(good.status, 0) << Describe(good);  // the file is good at level 0
  fs::remove(out);
  ExpectBadInput(
      dir,
      {"eval", "--params", exr, "--dirs", texels, "--level", "1", "--out", out},
      {texels + ":3:", "(3, 1)", "level 1", "2 x 1"});
  const std::string s_out = (dir / "s_out.csv").string();
  WriteText(s_out,
            "# clothfit-table 1\n"
            "theta_i,phi_i,theta_o,phi_o,s,t\n"
            "10,0,20,180,3,1\n"
            "10,0,20,180,4,0\n");
  ExpectBadInput(dir, {"eval", "--params", exr, "--dirs", s_out, "--out", out},
                 {s_out + ":4:", "(4, 0)", "level 0", "4 x 2"});
  for (const char* level : {"3", "-1"}) {
    ExpectBadInput(dir,
                   {"eval", "--params", exr, "--dirs", texels, "--level", level,
                    "--out", out},
                   {"--level", exr, "0 to 2", std::string("got ") + level});
  }
  // --level only goes with a mip map.
  const fs::path json_dir = DirWithInputs();
  ExpectBadInput(json_dir,
                 {"eval", "--params", (json_dir / "P.json").string(), "--dirs",
                  (json_dir / "D.csv").string(), "--level", "1", "--out",
                  (json_dir / "O.csv").string()},
                 {"--level", ".exr"});
}

}  // namespace
}  // namespace clothfit
