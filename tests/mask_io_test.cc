// Masks read from images: alpha, else luminance, threshold,
// inversion, any size, and clear errors.
#include "io/mask_io.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <fstream>
#include <string>
#include <vector>

#include "tests/io_test_util.h"

namespace clothfit {
namespace {

namespace fs = std::filesystem;
using testing_util::ErrorOf;
using testing_util::ExpectHas;

fs::path TestDir() { return testing_util::FreshTestDir("mask_io_test_"); }

// Writes an image of `channels` float channels (alpha last when
// `alpha`), 8-bit unless the extension is .exr.
void WriteImage(const fs::path& path, int width, int height, int channels,
                bool alpha, const std::vector<float>& pixels) {
  std::unique_ptr<OIIO::ImageOutput> out =
      OIIO::ImageOutput::create(path.string());
  ASSERT_TRUE(out);
  const bool exr = path.extension() == ".exr";
  OIIO::ImageSpec spec(width, height, channels,
                       exr ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
  spec.alpha_channel = alpha ? channels - 1 : -1;
  spec.attribute("oiio:UnassociatedAlpha", 1);
  ASSERT_TRUE(out->open(path.string(), spec));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()));
  ASSERT_TRUE(out->close());
}

std::vector<int> Opaque(const Mask& mask) {
  return std::vector<int>(mask.opaque.begin(), mask.opaque.end());
}

TEST(MaskIoTest, GreyRoundTripAtAnySize) {
  const fs::path dir = TestDir();
  const Mask mask =
      MaskFromRows({"#..#..#", ".#.....", "..##...", ".......", "######."});
  WriteMask(mask, (dir / "m.png").string());
  const Mask back = ReadMask((dir / "m.png").string());
  EXPECT_EQ(back.width, 7);
  EXPECT_EQ(back.height, 5);
  EXPECT_EQ(Opaque(back), Opaque(mask));
  EXPECT_NEAR(back.OpaqueFraction(), 12.0 / 35.0, 1e-12);
}

TEST(MaskIoTest, AlphaChannelWinsOverColour) {
  const fs::path dir = TestDir();
  // Bright colour but opaque alpha, dark colour but clear alpha.
  WriteImage(dir / "a.png", 3, 1, 4, true,
             {1, 1, 1, 1.0f, 0, 0, 0, 0.0f, 0.5f, 0.5f, 0.5f, 0.6f});
  const Mask mask = ReadMask((dir / "a.png").string());
  EXPECT_EQ(Opaque(mask), (std::vector<int>{1, 0, 1}));
  MaskReadOptions luminance;
  luminance.source = MaskSource::kLuminance;
  EXPECT_EQ(Opaque(ReadMask((dir / "a.png").string(), luminance)),
            (std::vector<int>{0, 1, 0}));
  MaskReadOptions high;
  high.threshold = 0.7;  // alpha 0.6 is now below the threshold
  EXPECT_EQ(Opaque(ReadMask((dir / "a.png").string(), high)),
            (std::vector<int>{1, 0, 0}));
}

TEST(MaskIoTest, LuminanceWeightsAndThreshold) {
  const fs::path dir = TestDir();
  // Red (luminance 0.2126), green (0.7152), blue (0.0722), white.
  WriteImage(dir / "rgb.png", 4, 1, 3, false,
             {1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1});
  EXPECT_EQ(Opaque(ReadMask((dir / "rgb.png").string())),
            (std::vector<int>{1, 0, 1, 0}));
  MaskReadOptions options;
  options.threshold = 0.8;
  EXPECT_EQ(Opaque(ReadMask((dir / "rgb.png").string(), options)),
            (std::vector<int>{1, 1, 1, 0}));
  options.invert = true;
  EXPECT_EQ(Opaque(ReadMask((dir / "rgb.png").string(), options)),
            (std::vector<int>{0, 0, 0, 1}));
}

TEST(MaskIoTest, FloatExrSingleChannel) {
  const fs::path dir = TestDir();
  WriteImage(dir / "m.exr", 2, 2, 1, false, {0.2f, 3.0f, 0.5f, 0.49f});
  EXPECT_EQ(Opaque(ReadMask((dir / "m.exr").string())),
            (std::vector<int>{1, 0, 0, 1}));
}

TEST(MaskIoTest, TilesAtItsBorders) {
  const Mask mask = MaskFromRows({"#..", "..."});
  EXPECT_TRUE(mask.Opaque(0, 0));
  EXPECT_TRUE(mask.Opaque(3, 2));
  EXPECT_TRUE(mask.Opaque(-3, -2));
  EXPECT_FALSE(mask.Opaque(-1, 0));
  EXPECT_FALSE(mask.Opaque(0, -1));
}

TEST(MaskIoTest, ClearErrors) {
  const fs::path dir = TestDir();
  const std::string missing = (dir / "missing.png").string();
  ExpectHas(ErrorOf([&] { ReadMask(missing); }),
            {missing, "No such file or directory"});
  // A pipe or device is not taken for a missing file, and not opened (an
  // image library seeks; a pipe would block).
  const std::string fifo = (dir / "fifo.png").string();
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  ExpectHas(ErrorOf([&] { ReadMask(fifo); }), {fifo, "not a regular file"});
  ExpectHas(ErrorOf([&] { ReadMask("/dev/zero"); }),
            {"/dev/zero", "not a regular file"});
  const std::string loop = (dir / "loop.png").string();
  fs::create_symlink(loop, loop);
  ExpectHas(ErrorOf([&] { ReadMask(loop); }),
            {loop, "Too many levels of symbolic links"});
  const std::string text = (dir / "text.png").string();
  std::ofstream(text) << "not an image\n";
  ExpectHas(ErrorOf([&] { ReadMask(text); }), {text, "cannot read mask"});
  WriteMask(MaskFromRows({"#."}), (dir / "g.png").string());
  MaskReadOptions alpha;
  alpha.source = MaskSource::kAlpha;
  ExpectHas(ErrorOf([&] { ReadMask((dir / "g.png").string(), alpha); }),
            {"g.png", "no alpha channel"});
  for (double threshold : {0.0, 1.5, -1.0}) {
    MaskReadOptions bad;
    bad.threshold = threshold;
    ExpectHas(ErrorOf([&] { ReadMask((dir / "g.png").string(), bad); }),
              {"g.png", "threshold"});
  }
  ExpectHas(ErrorOf([&] { MaskFromRows({"#.", "#"}); }), {"row 1"});
  ExpectHas(
      ErrorOf([&] { WriteMask(MaskFromRows({"#"}), (dir / "x").string()); }),
      {"extension"});
  EXPECT_FALSE(fs::exists(dir / "x"));
}

}  // namespace
}  // namespace clothfit
