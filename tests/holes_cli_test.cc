// clothfit holes analyze|eval|truth and clothfit fit --model holes: files,
// values against the library, exit statuses.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "data_synthetic/holes_truth.h"
#include "holes/hole_texture.h"
#include "io/hole_exr.h"
#include "io/mask_io.h"
#include "io/params_json.h"
#include "io/table.h"
#include "tests/cli_test_util.h"
#include "tests/io_test_util.h"
#include "tests/pyramid_test_util.h"

namespace clothfit {
namespace {

namespace fs = std::filesystem;
using testing_util::Describe;
using testing_util::ReadText;
using testing_util::RunClothfit;
using testing_util::RunResult;
using testing_util::WriteText;

fs::path TestDir() { return testing_util::FreshTestDir("holes_cli_test_"); }

// View directions over theta x phi (degrees) as a transmittance table.
std::string WriteDirections(const fs::path& dir) {
  MeasurementTable table;
  table.quantity = Quantity::kTransmittance;
  table.channels = 1;
  for (double theta : {0.0, 15.0, 30.0, 45.0, 55.0, 65.0}) {
    for (double phi : {0.0, 30.0, 45.0, 120.0, 250.0}) {
      TableRow row;
      row.wo = DirectionFromAngles(Radians(theta), Radians(phi));
      table.rows.push_back(row);
    }
  }
  const std::string path = (dir / "dirs.csv").string();
  WriteTable(table, path);
  return path;
}

std::string WriteNet(const fs::path& dir) {
  const std::string path = (dir / "net.png").string();
  WriteMask(SquareHoleMask(5, 1), path);
  return path;
}

TEST(HolesCliTest, AnalyzeWritesTheCountPyramid) {
  const fs::path dir = TestDir();
  const std::string mask_path = (dir / "m.png").string();
  WriteMask(RandomMask(12, 10, 0.4, 3), mask_path);
  const std::string counts = (dir / "c.exr").string();
  const std::string distances = (dir / "d.exr").string();
  const RunResult r =
      RunClothfit(dir, {"holes", "analyze", "--mask", mask_path, "--out",
                        counts, "--distances", distances});
  ASSERT_EQ(r.status, 0) << Describe(r);
  EXPECT_NE(r.out.find("12 x 10 texels"), std::string::npos) << r.out;
  const Mask mask = ReadMask(mask_path);
  const HoleTexture expected = AnalyzeMask(mask, true);
  std::string metadata;
  testing_util::ExpectSamePyramid(
      ReadCountPyramid(counts, CountKind::kHoleCounts, &metadata),
      expected.counts);
  EXPECT_NE(metadata.find("m.png"), std::string::npos);
  testing_util::ExpectSamePyramid(
      ReadCountPyramid(distances, CountKind::kHoleDistances),
      expected.distances);
}

TEST(HolesCliTest, EvalMatchesTheLibrary) {
  const fs::path dir = TestDir();
  const std::string mask_path = (dir / "m.png").string();
  WriteMask(RandomMask(16, 12, 0.35, 8), mask_path);
  const std::string dirs = WriteDirections(dir);
  const HoleTexture texture = AnalyzeMask(ReadMask(mask_path), true);
  const MeasurementTable views = ReadTable(dirs).table;
  for (const std::string method : {"alg31", "extension"}) {
    for (const std::string level : {"top", "0"}) {
      const std::string out = (dir / ("o_" + method + level + ".csv")).string();
      const RunResult r = RunClothfit(
          dir, {"holes", "eval", "--mask", mask_path, "--thickness", "1.5",
                "--wall-color", "0.2,0.4,0.6", "--method", method, "--level",
                level, "--dirs", dirs, "--out", out});
      ASSERT_EQ(r.status, 0) << Describe(r);
      const MeasurementTable table = ReadTable(out).table;
      EXPECT_EQ(table.quantity, Quantity::kTransmittance);
      ASSERT_EQ(table.channels, 3);
      ASSERT_EQ(table.rows.size(), views.rows.size());
      const int l = level == "top" ? texture.counts.levels() - 1 : 0;
      for (size_t i = 0; i < views.rows.size(); ++i) {
        const HoleRatios ratios =
            EvaluateTile(texture, *ParseHoleMethod(method), l,
                         ViewOffset(1.5, views.rows[i].wo));
        const glm::dvec3 wall(0.2, 0.4, 0.6);
        for (int c = 0; c < 3; ++c) {
          EXPECT_NEAR(table.rows[i].value[c],
                      ratios.transparent + wall[c] * ratios.occluded, 1e-12);
        }
      }
    }
  }
}

TEST(HolesCliTest, TruthThenFitRecoversTheThickness) {
  const fs::path dir = TestDir();
  const std::string mask = WriteNet(dir);
  const std::string dirs = WriteDirections(dir);
  const std::string truth = (dir / "truth.csv").string();
  RunResult r =
      RunClothfit(dir, {"holes", "truth", "--mask", mask, "--thickness", "2",
                        "--dirs", dirs, "--out", truth, "--rays", "200000"});
  ASSERT_EQ(r.status, 0) << Describe(r);
  const MeasurementTable table = ReadTable(truth).table;
  const Mask net = SquareHoleMask(5, 1);
  const Footprint tile = TileFootprint(net, 200000);
  for (const TableRow& row : table.rows) {
    EXPECT_DOUBLE_EQ(row.value.x,
                     HoleTruth(net, ViewOffset(2.0, row.wo), tile).transparent);
  }
  const std::string params = (dir / "p.json").string();
  r = RunClothfit(dir, {"fit", "--model", "holes", "--data", truth, "--mask",
                        mask, "--out", params});
  ASSERT_EQ(r.status, 0) << Describe(r);
  const ParamFile fit = ReadParamFile(params);
  EXPECT_NEAR(ModelOf<HolesModel>(fit, params).params.thickness_texels, 2.0,
              0.02);
  EXPECT_EQ(fit.holes.path, mask);
  EXPECT_EQ(fit.holes.method, HoleMethod::kExtension);
  EXPECT_NE(fit.fit_json.find("\"stddev\":{\"thickness_texels\""),
            std::string::npos)
      << fit.fit_json;
  // The fitted file drives eval.
  const std::string out = (dir / "o.csv").string();
  r = RunClothfit(dir, {"holes", "eval", "--mask", mask, "--params", params,
                        "--dirs", dirs, "--out", out});
  ASSERT_EQ(r.status, 0) << Describe(r);
  const MeasurementTable evaluated = ReadTable(out).table;
  for (size_t i = 0; i < table.rows.size(); ++i) {
    EXPECT_NEAR(evaluated.rows[i].value.x, table.rows[i].value.x, 0.01);
  }
  // So does the general eval, reading the mask the file names: the same
  // values as holes eval (the same method and level).
  const std::string general = (dir / "g.csv").string();
  r = RunClothfit(
      dir, {"eval", "--params", params, "--dirs", dirs, "--out", general});
  ASSERT_EQ(r.status, 0) << Describe(r);
  const MeasurementTable same = ReadTable(general).table;
  ASSERT_EQ(same.rows.size(), evaluated.rows.size());
  for (size_t i = 0; i < same.rows.size(); ++i) {
    EXPECT_NEAR(same.rows[i].value.x, evaluated.rows[i].value.x, 1e-12);
  }
  // The fit stored its mask's tile: without the mask, eval gives the same.
  EXPECT_NE(ModelOf<HolesModel>(fit, params).tile, nullptr);
  fs::rename(mask, dir / "moved.png");
  const std::string alone = (dir / "alone.csv").string();
  r = RunClothfit(dir,
                  {"eval", "--params", params, "--dirs", dirs, "--out", alone});
  ASSERT_EQ(r.status, 0) << Describe(r);
  const MeasurementTable from_tile = ReadTable(alone).table;
  ASSERT_EQ(from_tile.rows.size(), same.rows.size());
  for (size_t i = 0; i < same.rows.size(); ++i) {
    EXPECT_EQ(from_tile.rows[i].value, same.rows[i].value);
  }
}

// holes tile writes the file with its mask's tile: the general eval of the
// result (no mask read) equals that of the original (its mask read), and
// at level 1 it equals holes eval of the mask at level 1; a level with more
// texels than a file holds is refused.
TEST(HolesCliTest, TileCommandStoresTheMasksTile) {
  const fs::path dir = TestDir();
  const std::string dirs = WriteDirections(dir);
  const std::string mask = WriteNet(dir);
  const std::string original = (dir / "net.json").string();
  WriteText(original,
            "{\"model\": \"holes\", \"thickness_texels\": 1.5, "
            "\"wall_color\": 0.3, \"mask\": \"net.png\"}");
  auto eval = [&](const std::vector<std::string>& args) {
    const std::string out = (dir / "o.csv").string();
    std::vector<std::string> all = args;
    all.insert(all.end(), {"--dirs", dirs, "--out", out});
    const RunResult r = RunClothfit(dir, all);
    EXPECT_EQ(r.status, 0) << Describe(r);
    return ReadTable(out).table;
  };
  const std::string top = (dir / "top.json").string();
  const std::string level1 = (dir / "level1.json").string();
  RunResult r =
      RunClothfit(dir, {"holes", "tile", "--params", original, "--out", top});
  ASSERT_EQ(r.status, 0) << Describe(r);
  r = RunClothfit(dir, {"holes", "tile", "--params", original, "--level", "1",
                        "--out", level1});
  ASSERT_EQ(r.status, 0) << Describe(r);
  const ParamFile file = ReadParamFile(level1);
  const HolesModel& model = ModelOf<HolesModel>(file, level1);
  ASSERT_NE(model.tile, nullptr);
  EXPECT_EQ(model.tile->texels.counts.size(), 9u);  // 6 x 6 mask: 3 x 3
  EXPECT_EQ(file.holes.path, "net.png");
  const MeasurementTable from_mask = eval({"eval", "--params", original});
  const MeasurementTable from_tile = eval({"eval", "--params", top});
  const MeasurementTable mask_level1 = eval(
      {"holes", "eval", "--mask", mask, "--params", original, "--level", "1"});
  const MeasurementTable tile_level1 = eval({"eval", "--params", level1});
  ASSERT_EQ(from_tile.rows.size(), from_mask.rows.size());
  ASSERT_EQ(tile_level1.rows.size(), mask_level1.rows.size());
  for (size_t i = 0; i < from_mask.rows.size(); ++i) {
    EXPECT_EQ(from_tile.rows[i].value, from_mask.rows[i].value);
    EXPECT_NEAR(tile_level1.rows[i].value.x, mask_level1.rows[i].value.x,
                1e-12);
  }
  const std::string big = (dir / "big.png").string();
  WriteMask(SquareHoleMask(100, 28), big);  // 128 x 128
  testing_util::ExpectBadInput(
      dir,
      {"holes", "tile", "--params", original, "--mask", big, "--level", "0",
       "--out", (dir / "big.json").string()},
      {"16384 texels", "at most 4096"});
}

TEST(HolesCliTest, GeneralCommandsNeedTheMaskAndTransmittance) {
  const fs::path dir = TestDir();
  const std::string dirs = WriteDirections(dir);
  WriteText(dir / "no_mask.json",
            "{\"model\": \"holes\", \"thickness_texels\": 1}");
  testing_util::ExpectBadInput(
      dir,
      {"eval", "--params", (dir / "no_mask.json").string(), "--dirs", dirs,
       "--out", (dir / "o.csv").string()},
      {"no_mask.json", "needs its mask"});
  // With its mask, a holes model predicts transmittance only.
  WriteNet(dir);
  WriteText(dir / "net.json",
            "{\"model\": \"holes\", \"thickness_texels\": 1, \"mask\": "
            "\"net.png\"}");
  const std::string brdf = (dir / "brdf.csv").string();
  WriteText(brdf, "theta_i,phi_i,theta_o,phi_o\n0,0,30,0\n");
  testing_util::ExpectBadInput(
      dir,
      {"eval", "--params", (dir / "net.json").string(), "--dirs", brdf, "--out",
       (dir / "o.csv").string()},
      {"brdf.csv", "holes model predicts transmittance"});
  testing_util::ExpectBadInput(
      dir,
      {"synth", "--params", (dir / "net.json").string(), "--out",
       (dir / "s.csv").string()},
      {"holes model predicts transmittance"});
}

TEST(HolesCliTest, ChartsArePngWithCsv) {
  const fs::path dir = TestDir();
  const std::string mask = WriteNet(dir);
  const std::string chart = (dir / "chart.png").string();
  RunResult r = RunClothfit(
      dir, {"holes", "eval", "--mask", mask, "--thickness", "2", "--chart",
            chart, "--azimuth", "30", "--rays", "20000"});
  ASSERT_EQ(r.status, 0) << Describe(r);
  EXPECT_EQ(ReadText(chart).substr(0, 4), "\x89PNG");
  const std::string csv = ReadText(dir / "chart.csv");
  EXPECT_NE(csv.find("theta_deg,alg31,extension,truth"), std::string::npos);
  EXPECT_NE(csv.find("\n85,"), std::string::npos) << csv;
  const std::string map = (dir / "map.png").string();
  r = RunClothfit(dir, {"holes", "eval", "--error-map", map, "--hole-sizes",
                        "1,3", "--thicknesses", "1,2", "--samples", "8"});
  ASSERT_EQ(r.status, 0) << Describe(r);
  EXPECT_EQ(ReadText(map).substr(0, 4), "\x89PNG");
  const std::string map_csv = ReadText(dir / "map.csv");
  EXPECT_NE(map_csv.find("\n3,2,"), std::string::npos) << map_csv;
}

TEST(HolesCliTest, BadInputIsExitTwoWithAClearMessage) {
  const fs::path dir = TestDir();
  const std::string mask = WriteNet(dir);
  const std::string dirs = WriteDirections(dir);
  const std::string out = (dir / "o.csv").string();
  const std::string missing = (dir / "missing.png").string();
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"holes"}, "needs a subcommand"},
      {{"holes", "spin"}, "unknown holes subcommand 'spin'"},
      {{"holes", "analyze", "--mask", missing, "--out", out}, "missing.png"},
      {{"holes", "analyze", "--mask", mask, "--out", out, "--threshold", "2"},
       "--threshold"},
      {{"holes", "eval", "--mask", mask, "--thickness", "1", "--dirs", dirs,
        "--out", out, "--method", "magic"},
       "--method"},
      {{"holes", "eval", "--mask", mask, "--thickness", "-1", "--dirs", dirs,
        "--out", out},
       "thickness_texels"},
      {{"holes", "eval", "--mask", mask, "--thickness", "1", "--dirs", dirs,
        "--out", out, "--level", "9"},
       "--level"},
      {{"holes", "eval", "--mask", mask, "--thickness", "1", "--chart",
        (dir / "c.jpg").string()},
       ".png"},
      {{"holes", "truth", "--mask", mask, "--dirs", dirs, "--out", out},
       "--thickness"},
      {{"fit", "--model", "holes", "--data", dirs, "--out", out}, "--mask"},
  };
  for (const auto& [args, piece] : cases) {
    // Exit 2, one "error: " line holding the piece, no output.
    testing_util::ExpectBadInput(dir, args, {piece});
    EXPECT_FALSE(fs::exists(out)) << args.back();
  }
  // A reflectance table cannot be fitted.
  const std::string brdf = (dir / "brdf.csv").string();
  testing_util::WriteText(brdf,
                          "theta_i,phi_i,theta_o,phi_o,value\n0,0,0,0,1\n");
  const RunResult r = RunClothfit(dir, {"fit", "--model", "holes", "--data",
                                        brdf, "--mask", mask, "--out", out});
  EXPECT_EQ(r.status, 2) << Describe(r);
  EXPECT_NE(r.err.find("transmittance"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
}

TEST(HolesCliTest, HelpForEveryCommand) {
  const fs::path dir = TestDir();
  for (const std::vector<std::string>& args :
       std::vector<std::vector<std::string>>{
           {"holes", "--help"},
           {"holes", "analyze", "--help"},
           {"holes", "eval", "--help"},
           {"holes", "truth", "--help"},
           {"holes", "tile", "--help"},
           {"fit", "--model", "holes", "--help"}}) {
    const RunResult r = RunClothfit(dir, args);
    EXPECT_EQ(r.status, 0) << Describe(r);
    EXPECT_NE(r.out.find("usage:"), std::string::npos) << r.out;
  }
}

}  // namespace
}  // namespace clothfit
