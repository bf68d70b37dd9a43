// clothfit fit --region and clothfit merge (docs/scale.md): a texel map
// fitted in blocks and merged is the map of one fit of the whole stack,
// bit for bit; bad regions and parts that do not tile the texture are bad
// input naming the option or the block.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "io/param_mipmap.h"
#include "tests/cli_test_util.h"
#include "tests/io_test_util.h"

namespace clothfit {
namespace {

namespace fs = std::filesystem;
using testing_util::Describe;
using testing_util::ExpectBadInput;
using testing_util::RunClothfit;
using testing_util::RunResult;
using testing_util::WroteTextureMap;

fs::path TestDir() {
  return testing_util::FreshTestDir("lafortune_merge_test_");
}

// A virtual-gonioreflectometer stack of texels x texels (16 direction
// pairs): dir/stack/m.csv.
std::string WriteStack(const fs::path& dir, const std::string& pattern,
                       int texels) {
  const std::string manifest = (dir / "stack" / "m.csv").string();
  fs::create_directories(dir / "stack");
  const RunResult r = RunClothfit(
      dir, {"synth", "--gonio", pattern, "--texels", std::to_string(texels),
            "--directions", "4", "--stack", manifest});
  EXPECT_EQ(r.status, 0) << Describe(r);
  return manifest;
}

std::vector<std::string> Concat(std::vector<std::string> a,
                                const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

// Writes the parts of `block` x `block` texels into dir/parts.
void FitParts(const fs::path& dir, const std::string& manifest, int texels,
              int block, const std::vector<std::string>& options) {
  fs::create_directories(dir / "parts");
  for (int y = 0; y < texels; y += block) {
    for (int x = 0; x < texels; x += block) {
      const std::string region = std::to_string(x) + "," + std::to_string(y) +
                                 "," + std::to_string(block) + "," +
                                 std::to_string(block);
      const std::string part =
          (dir / "parts" /
           ("part_" + std::to_string(x) + "_" + std::to_string(y) + ".exr"))
              .string();
      const RunResult r = RunClothfit(
          dir, Concat({"fit", "--model", "lafortune", "--stack", manifest,
                       "--mip", "--region", region, "--out", part},
                      options));
      ASSERT_TRUE(WroteTextureMap(r)) << region << "\n" << Describe(r);
    }
  }
}

// The same channels, levels, texels and index metadata, every float
// compared by its bits.
void ExpectSameMap(const std::string& a_path, const std::string& b_path) {
  const ParamMipmap a = ReadParamMipmap(a_path);
  const ParamMipmap b = ReadParamMipmap(b_path);
  ASSERT_EQ(a.channels, b.channels);
  ASSERT_EQ(a.levels.size(), b.levels.size());
  for (size_t l = 0; l < a.levels.size(); ++l) {
    ASSERT_EQ(a.levels[l].width, b.levels[l].width);
    ASSERT_EQ(a.levels[l].height, b.levels[l].height);
    for (size_t c = 0; c < a.channels.size(); ++c) {
      const std::vector<float>& x = a.levels[l].data[c];
      const std::vector<float>& y = b.levels[l].data[c];
      ASSERT_EQ(x.size(), y.size());
      EXPECT_EQ(std::memcmp(x.data(), y.data(), x.size() * sizeof(float)), 0)
          << "level " << l << " channel " << a.channels[c];
    }
  }
  EXPECT_EQ(a.metadata_json, b.metadata_json);
}

// Fits the stack in one process and in blocks, merges, compares.
void ExpectMergeEqualsOneFit(const fs::path& dir, const std::string& pattern,
                             int texels, int block,
                             const std::vector<std::string>& options) {
  const std::string manifest = WriteStack(dir, pattern, texels);
  const std::string single = (dir / "single.exr").string();
  const RunResult one =
      RunClothfit(dir, Concat({"fit", "--model", "lafortune", "--stack",
                               manifest, "--mip", "--out", single},
                              options));
  ASSERT_TRUE(WroteTextureMap(one)) << Describe(one);
  FitParts(dir, manifest, texels, block, options);
  const std::string merged = (dir / "merged.exr").string();
  const RunResult merge = RunClothfit(
      dir, {"merge", "--parts", (dir / "parts").string(), "--out", merged});
  ASSERT_TRUE(WroteTextureMap(merge)) << Describe(merge);
  // The same summary of the fits, but for the time and the file's name.
  EXPECT_EQ(merge.status, one.status);
  EXPECT_EQ(merge.err, one.err);
  ExpectSameMap(single, merged);
}

TEST(LafortuneMerge, BlocksMergeIntoTheOneProcessFitBitForBit) {
  // 8 x 8 texels in 4 blocks: levels 0-2 from the parts, 3 above them.
  ExpectMergeEqualsOneFit(TestDir(), "plain", 8, 4, {"--lobes", "1"});
}

TEST(LafortuneMerge, ToleranceAndPerTexelNormalsMergeBitForBit) {
  // A satin gonio has a normal map (each group's frame the mean of its
  // texels'); --tolerance tries lobe counts whose errors choose the start
  // of the level above; blocks of 2: levels 2 and 3 above them.
  ExpectMergeEqualsOneFit(TestDir(), "satin", 8, 2, {"--tolerance", "0.3"});
}

TEST(LafortuneMerge, MissingOrDoubledBlockIsBadInput) {
  const fs::path dir = TestDir();
  const std::string manifest = WriteStack(dir, "plain", 4);
  FitParts(dir, manifest, 4, 2, {"--lobes", "1"});
  const fs::path parts = dir / "parts";
  const std::string out = (dir / "merged.exr").string();
  ExpectBadInput(dir,
                 {"merge", "--parts",
                  (parts / "part_0_0.exr").string() + "," +
                      (parts / "part_2_0.exr").string() + "," +
                      (parts / "part_0_2.exr").string(),
                  "--out", out},
                 {"block 2,2,2,2 is missing", "1 of 4"});
  fs::copy_file(parts / "part_2_0.exr", parts / "part_copy.exr");
  ExpectBadInput(
      dir, {"merge", "--parts", parts.string(), "--out", out},
      {"block 2,0,2,2 is in two parts", "part_2_0.exr", "part_copy.exr"});
  EXPECT_FALSE(fs::exists(out));
  // A part of a fit with other options.
  fs::remove(parts / "part_copy.exr");
  const RunResult other =
      RunClothfit(dir, {"fit", "--model", "lafortune", "--stack", manifest,
                        "--mip", "--region", "2,2,2,2", "--lobes", "2", "--out",
                        (parts / "part_2_2.exr").string()});
  ASSERT_TRUE(WroteTextureMap(other)) << Describe(other);
  ExpectBadInput(dir, {"merge", "--parts", parts.string(), "--out", out},
                 {"part_2_2.exr", "the fit's options differ"});
  // A file that is not a part.
  ExpectBadInput(dir,
                 {"merge", "--parts", (dir / "stack" / "m_0000.exr").string(),
                  "--out", out},
                 {"m_0000.exr"});
}

TEST(LafortuneMerge, BadRegionIsBadInput) {
  const fs::path dir = TestDir();
  const std::string manifest = WriteStack(dir, "plain", 8);
  const std::string out = (dir / "part.exr").string();
  for (const auto& [region, piece] :
       std::vector<std::pair<std::string, std::string>>{
           {"0,0,3,4", "powers of two"},
           {"2,0,4,4", "multiples"},
           {"8,0,4,4", "not inside the texture of 8 x 8"},
           {"0,0,16,16", "does not divide the texture"},
           {"0,0,4", "X0,Y0,W,H"},
           {"0,0,4,x", "X0,Y0,W,H"}}) {
    ExpectBadInput(dir,
                   {"fit", "--model", "lafortune", "--stack", manifest, "--mip",
                    "--region", region, "--out", out},
                   {"--region", piece});
  }
  ExpectBadInput(dir,
                 {"fit", "--model", "lafortune", "--stack", manifest, "--mip",
                  "--region", "0,0,4,4", "--noise", "relative", "--out", out},
                 {"--noise", "--noise-floor"});
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
}  // namespace clothfit
