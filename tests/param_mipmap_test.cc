#include "io/param_mipmap.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfTiledInputFile.h>
#include <ImfTiledOutputFile.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "io/atomic_file.h"
#include "io/input_error.h"
#include "tests/io_test_util.h"

namespace clothfit {
namespace {

namespace fs = std::filesystem;

fs::path TestDir() { return testing_util::FreshTestDir("param_mipmap_test_"); }

// Rewrites `path` as clothfit 0.3 wrote it: without the index in its header,
// which then comes from the .exr.json beside it.
void StripHeaderIndex(const std::string& path) {
  const std::string legacy = path + ".legacy";
  {
    Imf::TiledInputFile in(path.c_str());
    ASSERT_NE(in.header().find("clothfit:index"), in.header().end());
    // Every attribute but the index, copied into a new header (OpenEXR
    // 3.1's Header::erase leaks the attribute it removes).
    Imf::Header header;
    for (auto it = in.header().begin(); it != in.header().end(); ++it) {
      if (std::string(it.name()) != "clothfit:index") {
        header.insert(it.name(), it.attribute());
      }
    }
    Imf::TiledOutputFile out(legacy.c_str(), header);
    out.copyPixels(in);
  }
  fs::rename(legacy, path);
}

// Rewrites `path` with its first value (level 0, the first channel in the
// EXR's alphabetical order, texel (0, 0)) replaced by `value`: a file
// clothfit's writer refuses to make.
void PoisonFirstValue(const std::string& path, float value) {
  const std::string poisoned = path + ".poisoned";
  {
    Imf::TiledInputFile in(path.c_str());
    Imf::TiledOutputFile out(poisoned.c_str(), in.header());
    for (int level = 0; level < in.numLevels(); ++level) {
      const int w = in.levelWidth(level);
      const int h = in.levelHeight(level);
      std::vector<std::vector<float>> planes;
      Imf::FrameBuffer frame;
      for (auto it = in.header().channels().begin();
           it != in.header().channels().end(); ++it) {
        planes.emplace_back(static_cast<size_t>(w) * h);
      }
      size_t c = 0;
      for (auto it = in.header().channels().begin();
           it != in.header().channels().end(); ++it, ++c) {
        frame.insert(
            it.name(),
            Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(planes[c].data()),
                       sizeof(float), sizeof(float) * w));
      }
      in.setFrameBuffer(frame);
      in.readTiles(0, in.numXTiles(level) - 1, 0, in.numYTiles(level) - 1,
                   level);
      if (level == 0) planes[0][0] = value;
      out.setFrameBuffer(frame);
      out.writeTiles(0, out.numXTiles(level) - 1, 0, out.numYTiles(level) - 1,
                     level);
    }
  }
  fs::rename(poisoned, path);
}

// A mip map of random values with `channels` channels over a width x height
// base, down to 1 x 1.
ParamMipmap RandomMipmap(int width, int height, int channels,
                         unsigned seed = 1) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<float> uniform(-1000.0f, 1000.0f);
  ParamMipmap mipmap;
  for (int c = 0; c < channels; ++c) {
    mipmap.channels.push_back("lut." + std::to_string(c / 3) + "." +
                              "RGB"[c % 3]);
  }
  while (true) {
    ParamImage image;
    image.width = width;
    image.height = height;
    image.data.resize(channels);
    for (std::vector<float>& values : image.data) {
      values.resize(static_cast<size_t>(width) * height);
      for (float& value : values) value = uniform(random);
    }
    mipmap.levels.push_back(std::move(image));
    if (width == 1 && height == 1) break;
    width = std::max(1, width / 2);
    height = std::max(1, height / 2);
  }
  return mipmap;
}

using testing_util::ErrorOf;
using testing_util::ExpectHas;

void ExpectSame(const ParamMipmap& a, const ParamMipmap& b) {
  EXPECT_EQ(a.channels, b.channels);
  ASSERT_EQ(a.levels.size(), b.levels.size());
  for (size_t l = 0; l < a.levels.size(); ++l) {
    EXPECT_EQ(a.levels[l].width, b.levels[l].width);
    EXPECT_EQ(a.levels[l].height, b.levels[l].height);
    ASSERT_EQ(a.levels[l].data.size(), b.levels[l].data.size());
    for (size_t c = 0; c < a.levels[l].data.size(); ++c) {
      // Bit-exact floats.
      ASSERT_EQ(a.levels[l].data[c], b.levels[l].data[c])
          << "level " << l << " channel " << a.channels[c];
    }
  }
}

int CountEntries(const fs::path& dir) {
  int entries = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    (void)entry;
    ++entries;
  }
  return entries;
}

TEST(ParamMipmapTest, RoundTripManyChannels) {
  const fs::path dir = TestDir();
  const std::string path = (dir / "params.exr").string();
  ParamMipmap mipmap = RandomMipmap(8, 4, 300);
  ASSERT_EQ(mipmap.levels.size(), 4u);  // 8x4, 4x2, 2x1, 1x1
  mipmap.metadata_json = R"({"views": [[0.5, 1.0], [2, 3]], "units": "sr^-1"})";
  WriteParamMipmap(mipmap, path);
  EXPECT_TRUE(fs::exists(path));
  EXPECT_TRUE(fs::exists(path + ".json"));
  EXPECT_EQ(CountEntries(dir), 2);  // No temporary files left.

  const ParamMipmap back = ReadParamMipmap(path);
  ExpectSame(back, mipmap);
  EXPECT_EQ(back.metadata_json,
            R"({"units":"sr^-1","views":[[0.5,1.0],[2,3]]})");

  const std::string index = ReadFileToString(path + ".json");
  for (const char* piece :
       {"\"format\": \"clothfit-param-mipmap 1\"", "\"exr\": \"params.exr\"",
        "\"width\": 8", "\"height\": 4", "\"levels\": 4", "\"lut.99.B\""}) {
    EXPECT_NE(index.find(piece), std::string::npos) << piece << "\n" << index;
  }
}

// A fit without mip levels writes the base level alone (ONE_LEVEL tiles).
TEST(ParamMipmapTest, RoundTripBaseLevelOnly) {
  const fs::path dir = TestDir();
  const std::string path = (dir / "base.exr").string();
  ParamMipmap mipmap = RandomMipmap(5, 3, 7);
  mipmap.levels.resize(1);
  WriteParamMipmap(mipmap, path);
  const ParamMipmap back = ReadParamMipmap(path);
  ASSERT_EQ(back.levels.size(), 1u);
  EXPECT_EQ(back.levels[0].width, 5);
  EXPECT_EQ(back.levels[0].height, 3);
  EXPECT_EQ(back.levels[0].data, mipmap.levels[0].data);
  EXPECT_EQ(back.channels, mipmap.channels);
}

TEST(ParamMipmapTest, RoundTripOddAndLargerSizes) {
  const fs::path dir = TestDir();
  for (const auto& [width, height] : {std::pair{1, 1}, std::pair{1, 7},
                                      std::pair{33, 5}, std::pair{70, 65}}) {
    const std::string path = (dir / ("p" + std::to_string(width) + "x" +
                                     std::to_string(height) + ".exr"))
                                 .string();
    const ParamMipmap mipmap = RandomMipmap(width, height, 5, width * height);
    WriteParamMipmap(mipmap, path);
    const ParamMipmap back = ReadParamMipmap(path);
    ExpectSame(back, mipmap);
    EXPECT_EQ(back.metadata_json, "{}");
  }
  // Writing again replaces the files.
  const std::string path = (dir / "p1x1.exr").string();
  const ParamMipmap other = RandomMipmap(2, 2, 3, 99);
  WriteParamMipmap(other, path);
  ExpectSame(ReadParamMipmap(path), other);
}

TEST(ParamMipmapTest, RejectsInconsistentMipmaps) {
  const fs::path dir = TestDir();
  const std::string path = (dir / "bad.exr").string();

  ParamMipmap missing_level = RandomMipmap(8, 4, 2);
  missing_level.levels.pop_back();
  ExpectHas(ErrorOf([&] { WriteParamMipmap(missing_level, path); }),
            {path, "needs 1 level or 4 levels", "got 3"});

  ParamMipmap wrong_size = RandomMipmap(8, 4, 2);
  wrong_size.levels[2].width = 1;
  ExpectHas(ErrorOf([&] { WriteParamMipmap(wrong_size, path); }),
            {path, "level 2 is 1 x 1, expected 2 x 1"});

  ParamMipmap wrong_channels = RandomMipmap(8, 4, 2);
  wrong_channels.levels[1].data.pop_back();
  ExpectHas(ErrorOf([&] { WriteParamMipmap(wrong_channels, path); }),
            {path, "level 1 has 1 channels, expected 2"});

  ParamMipmap wrong_data = RandomMipmap(8, 4, 2);
  wrong_data.levels[0].data[1].push_back(0.0f);
  ExpectHas(ErrorOf([&] { WriteParamMipmap(wrong_data, path); }),
            {path, "level 0", "has 33 values, expected 32"});

  ParamMipmap duplicate = RandomMipmap(2, 2, 2);
  duplicate.channels[1] = duplicate.channels[0];
  ExpectHas(ErrorOf([&] { WriteParamMipmap(duplicate, path); }),
            {path, "duplicate channel"});

  ParamMipmap no_channels;
  no_channels.levels.resize(1);
  no_channels.levels[0].width = no_channels.levels[0].height = 1;
  ExpectHas(ErrorOf([&] { WriteParamMipmap(no_channels, path); }),
            {path, "no channels"});

  ParamMipmap bad_metadata = RandomMipmap(2, 2, 1);
  bad_metadata.metadata_json = "{oops";
  ExpectHas(ErrorOf([&] { WriteParamMipmap(bad_metadata, path); }),
            {path, "metadata"});
  bad_metadata.metadata_json = "[1, 2]";
  ExpectHas(ErrorOf([&] { WriteParamMipmap(bad_metadata, path); }),
            {path, "metadata is not a JSON object"});

  EXPECT_EQ(CountEntries(dir), 0);  // Nothing written.

  ExpectHas(ErrorOf([&] {
              WriteParamMipmap(RandomMipmap(2, 2, 1),
                               (dir / "no_dir" / "x.exr").string());
            }),
            {"no_dir/x.exr", "cannot write"});
}

TEST(ParamMipmapTest, TruncatedExr) {
  const fs::path dir = TestDir();
  const std::string path = (dir / "cut.exr").string();
  WriteParamMipmap(RandomMipmap(64, 64, 20), path);
  const std::string full = ReadFileToString(path);
  for (size_t keep :
       {full.size() / 2, full.size() - 1, size_t{100}, size_t{10}, size_t{0}}) {
    std::ofstream(path, std::ios::binary | std::ios::trunc)
        .write(full.data(), static_cast<std::streamsize>(keep));
    ExpectHas(ErrorOf([&] { ReadParamMipmap(path); }), {path});
  }
}

TEST(ParamMipmapTest, CorruptExrBytes) {
  const fs::path dir = TestDir();
  const std::string path = (dir / "noise.exr").string();
  WriteParamMipmap(RandomMipmap(16, 16, 4), path);
  const std::string full = ReadFileToString(path);
  std::mt19937 random(7);
  for (int trial = 0; trial < 50; ++trial) {
    std::string bytes = full;
    for (int i = 0; i < 8; ++i) {
      bytes[random() % bytes.size()] = static_cast<char>(random());
    }
    std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
    // Either an error naming the file or a well-formed result; no crash.
    try {
      const ParamMipmap back = ReadParamMipmap(path);
      EXPECT_EQ(back.levels.size(), 5u);
    } catch (const InputError& error) {
      EXPECT_NE(std::string(error.what()).find(path), std::string::npos);
    }
  }
}

TEST(ParamMipmapTest, MissingFiles) {
  const fs::path dir = TestDir();
  const std::string path = (dir / "p.exr").string();
  // Neither file: the EXR the caller named is the one reported.
  std::string error = ErrorOf([&] { ReadParamMipmap(path); });
  EXPECT_EQ(error.rfind(path + ": cannot read", 0), 0u) << error;

  // The EXR is complete alone: its index is in its header.
  WriteParamMipmap(RandomMipmap(4, 4, 3), path);
  fs::remove(path + ".json");
  EXPECT_EQ(ReadParamMipmap(path).channels.size(), 3u);

  // A file of clothfit 0.3 (no index in its header) without its index
  // copy: named, with what it is.
  WriteParamMipmap(RandomMipmap(4, 4, 3), path);
  StripHeaderIndex(path);
  fs::remove(path + ".json");
  ExpectHas(ErrorOf([&] { ReadParamMipmap(path); }),
            {path + ".json: missing", "JSON index", "keep the two together"});

  WriteParamMipmap(RandomMipmap(4, 4, 3), path);
  fs::remove(path);
  error = ErrorOf([&] { ReadParamMipmap(path); });
  EXPECT_EQ(error.rfind(path + ": cannot read", 0), 0u) << error;
}

TEST(ParamMipmapTest, BadIndex) {
  const fs::path dir = TestDir();
  const std::string path = (dir / "p.exr").string();
  const std::string index_path = path + ".json";
  WriteParamMipmap(RandomMipmap(8, 4, 3), path);
  StripHeaderIndex(path);  // the index checks, on the .exr.json of 0.3
  const std::string good = ReadFileToString(index_path);
  auto with_index = [&](const std::string& text) {
    WriteFileAtomically(index_path, text);
    return ErrorOf([&] { ReadParamMipmap(path); });
  };
  auto replaced = [&](const std::string& from, const std::string& to) {
    std::string text = good;
    const size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return text.replace(at, from.size(), to);
  };

  // A channel the EXR does not have.
  ExpectHas(with_index(replaced("\"lut.0.R\"", "\"lobe0.Cx.R\"")),
            {path, "channel 'lobe0.Cx.R'", "missing"});
  ExpectHas(with_index("{not json"), {index_path, "invalid JSON"});
  ExpectHas(with_index(""), {index_path, "invalid JSON"});
  ExpectHas(with_index("[]"), {index_path, "object"});
  ExpectHas(with_index(replaced("clothfit-param-mipmap 1", "other 2")),
            {index_path, "'format'"});
  ExpectHas(with_index(replaced("\"width\": 8", "\"width\": \"8\"")),
            {index_path, "'width'"});
  ExpectHas(with_index(replaced("\"levels\": 4", "\"levels\": 3")),
            {index_path, "'levels'"});
  ExpectHas(with_index(replaced("\"width\": 8", "\"width\": 16")),
            {index_path, "'levels'"});
  ExpectHas(with_index(replaced("\"height\": 4", "\"height\": 5")),
            {path, "image is 8 x 4, index says 8 x 5"});
  ExpectHas(with_index(replaced("\"lut.0.G\"", "\"lut.0.R\"")),
            {index_path, "duplicate"});
  ExpectHas(with_index(replaced("\"metadata\": {}", "\"metadata\": 3")),
            {index_path, "'metadata'"});

  // A subset of the EXR's channels is fine.
  const ParamMipmap subset =
      (WriteFileAtomically(index_path, replaced(",\n    \"lut.0.B\"", "")),
       ReadParamMipmap(path));
  EXPECT_EQ(subset.channels.size(), 2u);
}

// The header's index is the one read: an .exr.json from another run (a kill
// between the renames, two writers racing) or a broken one changes nothing.
TEST(ParamMipmapTest, HeaderIndexIsAuthoritative) {
  const fs::path dir = TestDir();
  const std::string a = (dir / "a.exr").string();
  const std::string b = (dir / "b.exr").string();
  WriteParamMipmap(RandomMipmap(8, 4, 3, 1), a);
  WriteParamMipmap(RandomMipmap(4, 4, 6, 2), b);
  fs::copy_file(b + ".json", a + ".json", fs::copy_options::overwrite_existing);
  const ParamMipmap read = ReadParamMipmap(a);
  EXPECT_EQ(read.channels.size(), 3u);
  EXPECT_EQ(read.levels[0].width, 8);
  EXPECT_EQ(read.levels[0].data[0], RandomMipmap(8, 4, 3, 1).levels[0].data[0]);
  WriteFileAtomically(a + ".json", "{not json");
  EXPECT_EQ(ReadParamMipmap(a).channels.size(), 3u);
}

// NaN and infinity are neither written nor read: a renderer would show
// them as black texels or fireflies (an EXR holding NaN rendered NaN pixels).
TEST(ParamMipmapTest, NonFiniteValuesAreRefused) {
  const fs::path dir = TestDir();
  const std::string path = (dir / "p.exr").string();
  ParamMipmap bad = RandomMipmap(4, 4, 3);
  bad.levels[1].data[2][1] = std::numeric_limits<float>::quiet_NaN();
  ExpectHas(ErrorOf([&] { WriteParamMipmap(bad, path); }),
            {path, "not written", "channel 'lut.0.B' at level 1, texel (1, 0)",
             "NaN"});
  EXPECT_FALSE(fs::exists(path));
  for (const float value : {std::numeric_limits<float>::quiet_NaN(),
                            std::numeric_limits<float>::infinity()}) {
    WriteParamMipmap(RandomMipmap(4, 4, 3), path);
    PoisonFirstValue(path, value);
    ExpectHas(ErrorOf([&] { ReadParamMipmap(path); }),
              {path, "channel 'lut.0.B' at level 0, texel (0, 0) is",
               std::isnan(value) ? "NaN" : "infinite"});
  }
}

// The bands of `mipmap`: fill copies the rows asked for; `calls` records
// (level, y0, rows) of each call.
ParamMipmapBands BandsOf(const ParamMipmap& mipmap,
                         std::vector<std::array<int, 3>>* calls) {
  ParamMipmapBands bands;
  bands.channels = mipmap.channels;
  bands.width = mipmap.levels[0].width;
  bands.height = mipmap.levels[0].height;
  bands.mipmapped = mipmap.levels.size() > 1;
  bands.metadata_json = mipmap.metadata_json;
  bands.fill = [&mipmap, calls](int level, int y0, ParamImage* band) {
    calls->push_back({level, y0, band->height});
    const ParamImage& image = mipmap.levels[level];
    ASSERT_EQ(band->width, image.width);
    ASSERT_EQ(band->data.size(), image.data.size());
    for (size_t c = 0; c < image.data.size(); ++c) {
      ASSERT_EQ(band->data[c].size(),
                static_cast<size_t>(band->width) * band->height);
      std::copy_n(
          image.data[c].begin() + static_cast<ptrdiff_t>(y0) * image.width,
          band->data[c].size(), band->data[c].begin());
    }
  };
  return bands;
}

// Written a band at a time, a map is the same file, byte for byte, as
// written whole; the bands cover each level once, top to bottom, 32 rows
// at most.
TEST(ParamMipmapTest, BandsWriteTheSameFileAsWholeLevels) {
  const fs::path whole = TestDir() / "whole";
  const fs::path banded = TestDir() / "banded";
  fs::create_directories(whole);
  fs::create_directories(banded);
  for (const auto& [width, height, levels] :
       {std::array{70, 81, 0}, std::array{33, 5, 0}, std::array{40, 65, 1}}) {
    ParamMipmap mipmap = RandomMipmap(width, height, 4, width + height);
    if (levels == 1) mipmap.levels.resize(1);
    mipmap.metadata_json = R"({"kind": "test"})";
    const std::string name = "p" + std::to_string(width) + ".exr";
    WriteParamMipmap(mipmap, (whole / name).string());
    std::vector<std::array<int, 3>> calls;
    WriteParamMipmapBands(BandsOf(mipmap, &calls), (banded / name).string());
    EXPECT_EQ(ReadFileToString((banded / name).string()),
              ReadFileToString((whole / name).string()))
        << name;
    EXPECT_EQ(ReadFileToString((banded / name).string() + ".json"),
              ReadFileToString((whole / name).string() + ".json"));
    std::vector<std::array<int, 3>> expected;
    for (size_t level = 0; level < mipmap.levels.size(); ++level) {
      for (int y0 = 0; y0 < mipmap.levels[level].height; y0 += 32) {
        expected.push_back({static_cast<int>(level), y0,
                            std::min(32, mipmap.levels[level].height - y0)});
      }
    }
    EXPECT_EQ(calls, expected) << name;
  }
}

// A non-finite value in a band fails with its place in the level and
// leaves the files as they were.
TEST(ParamMipmapTest, BandsRefuseNonFiniteValues) {
  const fs::path dir = TestDir();
  const std::string path = (dir / "p.exr").string();
  const ParamMipmap good = RandomMipmap(70, 80, 3, 4);
  WriteParamMipmap(good, path);
  const std::string before = ReadFileToString(path);
  ParamMipmap bad = good;
  bad.levels[1].data[2][35 * 35 + 3] = std::numeric_limits<float>::infinity();
  std::vector<std::array<int, 3>> calls;
  ExpectHas(ErrorOf([&] { WriteParamMipmapBands(BandsOf(bad, &calls), path); }),
            {path, "not written",
             "channel 'lut.0.B' at level 1, texel (3, 35) is infinite"});
  EXPECT_EQ(ReadFileToString(path), before);
  EXPECT_EQ(CountEntries(dir), 2);  // No temporary files left.
}

TEST(ParamMipmapTest, NotAMipmappedExr) {
  const fs::path dir = TestDir();
  const std::string path = (dir / "p.exr").string();
  WriteParamMipmap(RandomMipmap(4, 4, 1), path);
  // Not an EXR at all.
  WriteFileAtomically(path, "this is not an OpenEXR file");
  ExpectHas(ErrorOf([&] { ReadParamMipmap(path); }), {path});
}

}  // namespace
}  // namespace clothfit
