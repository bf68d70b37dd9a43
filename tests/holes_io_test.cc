// Files of semi-transparent textures with thickness: the count
// pyramids as mip-mapped OpenEXR files with a JSON index (nine channels,
// every level, read back exactly; damaged files are clear errors) and the
// holes parameter file.
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "data_synthetic/holes_truth.h"
#include "holes/hole_texture.h"
#include "io/hole_exr.h"
#include "io/param_mipmap.h"
#include "io/params_json.h"
#include "tests/io_test_util.h"
#include "tests/pyramid_test_util.h"

namespace clothfit {
namespace {

namespace fs = std::filesystem;
using testing_util::ErrorOf;
using testing_util::ExpectHas;
using testing_util::ExpectSamePyramid;

fs::path TestDir() { return testing_util::FreshTestDir("holes_io_test_"); }

TEST(HolesExrTest, RoundTripOfCountsAndDistances) {
  const fs::path dir = TestDir();
  const HoleTexture texture = AnalyzeMask(RandomMask(37, 20, 0.4, 9), true);
  const std::string counts = (dir / "c.exr").string();
  const std::string distances = (dir / "d.exr").string();
  WriteCountPyramid(texture.counts, CountKind::kHoleCounts,
                    "{\"mask\": \"m.png\"}", counts);
  WriteCountPyramid(texture.distances, CountKind::kHoleDistances, "",
                    distances);
  // A tiled MIPMAP_LEVELS file with all six levels and nine channels.
  const ParamMipmap raw = ReadParamMipmap(counts);
  EXPECT_EQ(raw.levels.size(), 6u);
  EXPECT_EQ(raw.channels.size(), 9u);
  EXPECT_EQ(raw.channels.front(), "walls.top");
  EXPECT_EQ(raw.channels.back(), "opaques");
  std::string metadata;
  ExpectSamePyramid(ReadCountPyramid(counts, CountKind::kHoleCounts, &metadata),
                    texture.counts);
  ExpectHas(metadata, {"\"mask\":\"m.png\"", "clothfit-hole-counts 1"});
  ExpectSamePyramid(ReadCountPyramid(distances, CountKind::kHoleDistances),
                    texture.distances);
  EXPECT_EQ(ReadParamMipmap(distances).channels.size(),
            static_cast<size_t>(kDistanceChannels));
}

TEST(HolesExrTest, DamagedFilesAreClearErrors) {
  const fs::path dir = TestDir();
  const HoleTexture texture = AnalyzeMask(RandomMask(8, 8, 0.5, 4), false);
  const std::string path = (dir / "c.exr").string();
  WriteCountPyramid(texture.counts, CountKind::kHoleCounts, "", path);
  // The wrong kind.
  ExpectHas(ErrorOf([&] { ReadCountPyramid(path, CountKind::kHoleDistances); }),
            {"c.exr.json", "kind"});
  ParamMipmap mipmap = ReadParamMipmap(path);
  // A level that is not the sum of the one below.
  mipmap.levels[2].data[kWallRight][3] += 1.0f;
  WriteParamMipmap(mipmap, path);
  ExpectHas(ErrorOf([&] { ReadCountPyramid(path, CountKind::kHoleCounts); }),
            {"c.exr", "level 2 texel (1, 1)", "walls.right", "sum"});
  // A fractional count at level 0.
  mipmap = ReadParamMipmap((dir / "c.exr").string());
  mipmap.levels[2].data[kWallRight][3] -= 1.0f;
  mipmap.levels[0].data[kOpaques][9] = 0.5f;
  WriteParamMipmap(mipmap, path);
  ExpectHas(ErrorOf([&] { ReadCountPyramid(path, CountKind::kHoleCounts); }),
            {"level 0 texel (1, 1)", "opaques", "integer"});
  // Missing files.
  ExpectHas(ErrorOf([&] {
              ReadCountPyramid((dir / "none.exr").string(),
                               CountKind::kHoleCounts);
            }),
            {"none.exr"});
}

TEST(HolesParamsTest, ArrayRoundTripAndRanges) {
  HolesParams p;
  p.thickness_texels = 2.5;
  p.wall_color = glm::dvec3(0.1, 0.2, 0.3);
  ASSERT_EQ(FlatSize(p), 4);
  double x[4];
  ToArray(p, x);
  HolesParams back;
  FromArray(x, &back);
  EXPECT_EQ(back.thickness_texels, 2.5);
  EXPECT_EQ(back.wall_color, p.wall_color);
  EXPECT_EQ(ValidateParams(p), "");
  p.thickness_texels = 0.0;
  ExpectHas(ValidateParams(p), {"thickness_texels"});
  p.thickness_texels = 1.0;
  p.wall_color.y = 1.5;
  ExpectHas(ValidateParams(p), {"wall_color", "component 1"});
}

TEST(HolesParamsTest, FileRoundTripAndErrors) {
  const fs::path dir = TestDir();
  ParamFile file;
  HolesModel model;
  model.params.thickness_texels = 1.0 / 3.0;
  model.params.wall_color = glm::dvec3(0.25, 0.5, 0.75);
  file.params = model;
  file.holes.path = "net.png";
  file.holes.threshold = 0.4;
  file.holes.method = HoleMethod::kAlgorithm31;
  file.fit_json = "{\"rms\":0.01}";
  const std::string path = (dir / "p.json").string();
  WriteParamFile(file, path);
  const ParamFile back = ReadParamFile(path);
  const HolesModel& read = ModelOf<HolesModel>(back, path);
  EXPECT_EQ(read.params.thickness_texels, 1.0 / 3.0);
  EXPECT_EQ(read.params.wall_color, model.params.wall_color);
  EXPECT_EQ(back.holes.path, "net.png");
  EXPECT_EQ(back.holes.threshold, 0.4);
  EXPECT_EQ(back.holes.method, HoleMethod::kAlgorithm31);
  EXPECT_EQ(back.fit_json, "{\"rms\":0.01}");
  // Read without its mask, the model has no tile: nothing can evaluate it.
  EXPECT_EQ(read.tile, nullptr);
  ExpectHas(ValidateModel(back.params), {"needs its mask"});
  // A grey wall colour may be one number; the rest is optional.
  const ParamFile grey = ParseParamFile(
      "{\"model\": \"holes\", \"thickness_texels\": 2, \"wall_color\": "
      "0.5}",
      "g.json");
  EXPECT_EQ(std::get<HolesModel>(grey.params).params.wall_color,
            glm::dvec3(0.5));
  const std::vector<std::pair<std::string, std::vector<std::string>>> bad = {
      {"{\"model\": \"holes\"}", {"'thickness_texels'", "missing"}},
      {"{\"model\": \"holes\", \"thickness_texels\": -1}",
       {"'thickness_texels'", "(0, 10000]"}},
      {"{\"model\": \"holes\", \"thickness_texels\": 1, \"wall_color\": "
       "[1, 2]}",
       {"'wall_color'"}},
      {"{\"model\": \"holes\", \"thickness_texels\": 1, \"method\": "
       "\"x\"}",
       {"'method'"}},
      {"{\"model\": \"holes\", \"thickness_texels\": 1, \"hight\": 2}",
       {"'hight'", "unknown key"}},
      {"{\"model\": \"holes\", \"thickness_texels\": 1,}", {"invalid JSON"}},
  };
  for (const auto& [text, pieces] : bad) {
    std::vector<std::string> all = pieces;
    all.push_back("b.json");
    const std::string message =
        ErrorOf([&] { ParseParamFile(text, "b.json"); });
    for (const std::string& piece : all) {
      EXPECT_NE(message.find(piece), std::string::npos)
          << "'" << piece << "' not in: " << message;
    }
  }
}

// A tile in the file: the model evaluates from it exactly as from the mask
// (every level a file may hold, both methods), and LoadHolesModel uses it
// without reading the mask (which is not there).
TEST(HolesParamsTest, TileInTheFileEvaluatesAsTheMask) {
  const fs::path dir = TestDir();
  const Mask mask =
      MaskFromRows({"##..#.#.", "#...#..#", "........", "###.##.#", "#.#.#..#",
                    "...#...#", "#....#..", "##.#.##."});
  const HoleTexture texture = AnalyzeMask(mask, true);
  for (HoleMethod method : {HoleMethod::kExtension, HoleMethod::kAlgorithm31}) {
    for (int level : {0, 1, kTopLevel}) {
      HolesModel model;
      model.params.thickness_texels = 1.7;
      model.params.wall_color = glm::dvec3(0.2, 0.4, 0.6);
      model.tile = std::make_shared<const HolesTile>(
          HolesTileOf(texture, method, level));
      ParamFile file(model);
      file.holes.path = "absent.png";
      file.holes.method = method;
      const std::string path = (dir / "tile.json").string();
      WriteParamFile(file, path);
      const ParamFile back = ReadParamFile(path);
      EXPECT_EQ(ValidateModel(back.params), "");
      const HolesModel loaded = LoadHolesModel(back, path);
      ASSERT_NE(loaded.tile, nullptr);
      for (const glm::dvec3& wo :
           {glm::dvec3(0, 0, 1), glm::normalize(glm::dvec3(0.7, -0.3, 0.4)),
            glm::normalize(glm::dvec3(-2.0, 1.0, 0.3))}) {
        const glm::dvec3 a = Transmittance(model, wo);
        const glm::dvec3 b = Transmittance(loaded, wo);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(b[c], a[c], 1e-15);
      }
    }
  }
}

// A file written without a method records the tile's, so that the tile
// reads back with the method it was made for.
TEST(HolesParamsTest, FileWithoutAMethodKeepsTheTilesMethod) {
  const Mask mask = MaskFromRows({"#..#", "....", "##.#", "...."});
  HolesModel model;
  model.tile = std::make_shared<const HolesTile>(HolesTileOf(
      AnalyzeMask(mask, false), HoleMethod::kAlgorithm31, kTopLevel));
  const ParamFile back =
      ParseParamFile(FormatParamFile(ParamFile(model)), "m.json");
  EXPECT_EQ(back.holes.method, HoleMethod::kAlgorithm31);
  ASSERT_NE(std::get<HolesModel>(back.params).tile, nullptr);
  EXPECT_EQ(std::get<HolesModel>(back.params).tile->method,
            HoleMethod::kAlgorithm31);
}

TEST(HolesParamsTest, DamagedTilesNameTheKey) {
  const std::string head =
      "{\"model\": \"holes\", \"thickness_texels\": 1, \"method\": "
      "\"alg31\", \"tile\": ";
  const std::string counts9 = "[1, 0, 0, 0, 1, 0, 0, 0, 0]";
  const std::vector<std::pair<std::string, std::vector<std::string>>> bad = {
      {"[]", {"'tile'", "JSON object"}},
      {"{\"area\": 1, \"texels\": [], \"counts\": []}",
       {"'tile.texels'", "1 to 4096"}},
      {"{\"area\": 1, \"texels\": [1], \"counts\": [[1, 2]]}",
       {"'tile.counts[0]'", "9 numbers"}},
      {"{\"area\": 2, \"texels\": [1], \"counts\": [" + counts9 + "]}",
       {"'tile.area'", "sum"}},
      {"{\"area\": 1, \"texels\": [1], \"counts\": [[3, 0, 0, 0, 0, 0, 0, "
       "0, 0]]}",
       {"'tile.counts[0]'", "[0, 2"}},
      {"{\"area\": 1, \"texels\": [-1], \"counts\": [" + counts9 + "]}",
       {"'tile.texels[0]'", "positive"}},
      {"{\"area\": 1, \"texels\": [1], \"counts\": [" + counts9 +
           "], \"extra\": 0}",
       {"'tile.extra'", "unknown key"}},
  };
  for (const auto& [tile, pieces] : bad) {
    const std::string message =
        ErrorOf([&] { ParseParamFile(head + tile + "}", "t.json"); });
    EXPECT_NE(message.find("t.json"), std::string::npos) << message;
    for (const std::string& piece : pieces) {
      EXPECT_NE(message.find(piece), std::string::npos)
          << "'" << piece << "' not in: " << message;
    }
  }
  // The extension needs the run counts.
  ExpectHas(ErrorOf([&] {
              ParseParamFile(
                  "{\"model\": \"holes\", \"thickness_texels\": 1, "
                  "\"tile\": {\"area\": 1, \"texels\": [1], \"counts\": [" +
                      counts9 + "]}}",
                  "t.json");
            }),
            {"t.json", "'tile'", "distances"});
}

}  // namespace
}  // namespace clothfit
