// Determinism: the same inputs and thread count give
// bit-identical output files; different thread counts give parameters equal
// within 1e-9 relative. Every fitter, through the command line.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "io/mask_io.h"
#include "io/param_mipmap.h"
#include "io/table.h"
#include "tests/cli_test_util.h"
#include "tests/io_test_util.h"

namespace clothfit {
namespace {

namespace fs = std::filesystem;
using testing_util::Describe;
using testing_util::ReadText;
using testing_util::RunClothfit;
using testing_util::RunResult;
using testing_util::WroteTextureMap;

constexpr double kThreadTolerance = 1e-9;  // relative

fs::path TestDir() { return testing_util::FreshTestDir("determinism_"); }

// Every number of `a` equals the one at the same place in `b` within a
// relative tolerance; the structure (keys, sizes, strings) is identical.
// The solver's diagnostics ("message", with Ceres' last cost change, and
// "iterations") are not results and may differ with the thread count.
void ExpectJsonNear(const nlohmann::json& a, const nlohmann::json& b,
                    double tolerance, const std::string& where) {
  ASSERT_EQ(a.type(), b.type()) << where;
  if (a.is_object()) {
    ASSERT_EQ(a.size(), b.size()) << where;
    for (auto it = a.begin(); it != a.end(); ++it) {
      if (it.key() == "message" || it.key() == "iterations") continue;
      ASSERT_TRUE(b.contains(it.key())) << where << "." << it.key();
      ExpectJsonNear(it.value(), b.at(it.key()), tolerance,
                     where + "." + it.key());
    }
  } else if (a.is_array()) {
    ASSERT_EQ(a.size(), b.size()) << where;
    for (size_t i = 0; i < a.size(); ++i) {
      ExpectJsonNear(a[i], b[i], tolerance,
                     where + "[" + std::to_string(i) + "]");
    }
  } else if (a.is_number_float()) {
    const double x = a.get<double>(), y = b.get<double>();
    EXPECT_LE(std::abs(x - y), tolerance * std::max(std::abs(x), 1e-300))
        << where << ": " << x << " vs " << y;
  } else {
    EXPECT_EQ(a, b) << where;
  }
}

// No value of `j` is null: a NaN or infinity is written as null, and a fit
// never emits either.
void ExpectNoNull(const nlohmann::json& j, const std::string& where) {
  EXPECT_FALSE(j.is_null()) << where;
  if (j.is_object()) {
    for (auto it = j.begin(); it != j.end(); ++it) {
      ExpectNoNull(it.value(), where + "." + it.key());
    }
  } else if (j.is_array()) {
    for (size_t i = 0; i < j.size(); ++i) {
      ExpectNoNull(j[i], where + "[" + std::to_string(i) + "]");
    }
  }
}

// Runs `fit_args` + `--threads N --out OUT` for the thread counts given,
// twice with the first: the two runs' files are byte-identical and hold no
// NaN or infinity, and every other thread count's file equals the first
// within kThreadTolerance.
void CheckFitDeterminism(const fs::path& dir,
                         const std::vector<std::string>& fit_args,
                         const std::vector<std::string>& threads) {
  std::vector<std::string> outs;
  auto run = [&](const std::string& n, const std::string& name) {
    const std::string out = (dir / name).string();
    std::vector<std::string> args = fit_args;
    args.insert(args.end(), {"--threads", n, "--out", out});
    const RunResult r = RunClothfit(dir, args);
    EXPECT_EQ(r.status, 0) << Describe(r);
    return out;
  };
  const std::string first = run(threads[0], "a.json");
  const std::string again = run(threads[0], "b.json");
  const std::string text = ReadText(first);
  ASSERT_FALSE(text.empty());
  EXPECT_EQ(text, ReadText(again)) << "same inputs, same threads";
  const nlohmann::json reference = nlohmann::json::parse(text);
  ExpectNoNull(reference, "file");
  for (size_t i = 1; i < threads.size(); ++i) {
    const std::string other = run(threads[i], "t" + threads[i] + ".json");
    ExpectJsonNear(reference, nlohmann::json::parse(ReadText(other)),
                   kThreadTolerance, "threads " + threads[i]);
  }
}

TEST(DeterminismTest, ThreadFitFilesAreBitIdentical) {
  const fs::path dir = TestDir();
  const std::string data = (dir / "T.csv").string();
  testing_util::WriteText(dir / "truth.json",
                          "{\"model\": \"thread\", \"eta\": 1.5, \"kd\": 0.2, "
                          "\"gamma_s_deg\": 6, \"gamma_v_deg\": 14, "
                          "\"albedo\": [0.3, 0.2, 0.1]}");
  ASSERT_EQ(RunClothfit(dir, {"synth", "--params",
                              (dir / "truth.json").string(), "--rows", "800",
                              "--noise", "0.02", "--seed", "7", "--out", data})
                .status,
            0);
  CheckFitDeterminism(dir, {"fit", "--model", "thread", "--data", data},
                      {"1", "2", "4"});
}

TEST(DeterminismTest, ClothFitFilesAreBitIdentical) {
  const fs::path dir = TestDir();
  const std::string data = (dir / "T.csv").string();
  ASSERT_EQ(
      RunClothfit(dir, {"synth", "--preset", "linen_plain", "--rows", "600",
                        "--noise", "0.02", "--seed", "3", "--out", data})
          .status,
      0);
  CheckFitDeterminism(dir,
                      {"fit", "--model", "cloth", "--data", data, "--preset",
                       "linen_plain", "--max-iterations", "30"},
                      {"1", "2"});
}

TEST(DeterminismTest, SlabFitFilesAreBitIdentical) {
  const fs::path dir = TestDir();
  const std::string data = (dir / "S.csv").string();
  ASSERT_EQ(RunClothfit(dir, {"synth", "--model", "slab", "--tau", "0.2",
                              "--albedo", "0.6,0.5,0.4", "--noise", "0.01",
                              "--seed", "5", "--out", data})
                .status,
            0);
  CheckFitDeterminism(dir, {"fit", "--model", "slab", "--data", data},
                      {"1", "2"});
}

TEST(DeterminismTest, HolesFitFilesAreBitIdentical) {
  const fs::path dir = TestDir();
  const std::string mask = (dir / "net.png").string();
  WriteMask(MaskFromRows({"#####", "#..##", "#..##", "#####", "#####"}), mask);
  MeasurementTable views;
  views.quantity = Quantity::kTransmittance;
  views.channels = 1;
  for (double theta : {0.0, 20.0, 40.0, 55.0}) {
    for (double phi : {0.0, 60.0, 135.0}) {
      TableRow row;
      row.wo = DirectionFromAngles(theta * M_PI / 180.0, phi * M_PI / 180.0);
      row.wi = -row.wo;
      row.wi.z = -row.wi.z;
      views.rows.push_back(row);
    }
  }
  const std::string dirs = (dir / "dirs.csv").string();
  WriteTable(views, dirs);
  const std::string truth = (dir / "truth.csv").string();
  ASSERT_EQ(
      RunClothfit(dir, {"holes", "truth", "--mask", mask, "--thickness", "1.5",
                        "--dirs", dirs, "--out", truth, "--rays", "20000"})
          .status,
      0);
  CheckFitDeterminism(
      dir, {"fit", "--model", "holes", "--data", truth, "--mask", mask},
      {"1", "2"});
}

// Lafortune: per-texel fits in parallel write the same EXR and index for
// any thread count (each texel's fit is serial; levels go in order).
TEST(DeterminismTest, LafortuneMipmapIsBitIdenticalForAnyThreadCount) {
  const fs::path dir = TestDir();
  const std::string table = (dir / "g.csv").string();
  ASSERT_EQ(RunClothfit(dir, {"synth", "--gonio", "plain", "--texels", "4",
                              "--directions", "4", "--out", table})
                .status,
            0);
  // Each run in a folder of its own: the index names its EXR.
  std::vector<std::string> texts;
  for (const char* threads : {"1", "1", "2", "0"}) {
    const fs::path run_dir = dir / ("run" + std::to_string(texts.size()));
    fs::create_directories(run_dir);
    const std::string exr = (run_dir / "m.exr").string();
    const RunResult r = RunClothfit(
        dir, {"fit", "--model", "lafortune", "--data", table, "--lobes", "1",
              "--mip", "--threads", threads, "--out", exr});
    ASSERT_TRUE(WroteTextureMap(r)) << Describe(r);
    texts.push_back(ReadText(exr) + ReadText(exr + ".json"));
    ASSERT_GT(ReadParamMipmap(exr).levels.size(), 1u);
  }
  for (size_t i = 1; i < texts.size(); ++i) {
    EXPECT_TRUE(texts[0] == texts[i]) << "run " << i << " differs";
  }
}

}  // namespace
}  // namespace clothfit
