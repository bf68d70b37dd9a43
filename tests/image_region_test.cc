// Image stacks read by region (io/image_stack.h ReadStackOptions::region,
// ImageStackReader): the rows of a whole read inside the region, from
// scanline and tiled EXR and from PNG.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "io/image_stack.h"
#include "io/table.h"
#include "tests/io_test_util.h"

namespace clothfit {
namespace {

namespace fs = std::filesystem;
using testing_util::ErrorOf;
using testing_util::ExpectHas;

fs::path TestDir() { return testing_util::FreshTestDir("image_region_test_"); }

// `pairs` images of width x height rgb pixels with alpha, values in [0, 1]
// (exact in a float EXR; PNG rounds both reads alike).
MeasurementTable Stack(int pairs, int width, int height) {
  std::mt19937 random(7);
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  MeasurementTable table;
  table.quantity = Quantity::kCosineWeighted;
  table.channels = 3;
  table.has_texels = true;
  table.has_alpha = true;
  for (int k = 0; k < pairs; ++k) {
    const glm::dvec3 wi = DirectionFromAngles(0.1 + 0.3 * k, 0.5 * k);
    const glm::dvec3 wo = DirectionFromAngles(0.7 + 0.2 * k, 3.0 - 0.4 * k);
    for (int t = 0; t < height; ++t) {
      for (int s = 0; s < width; ++s) {
        TableRow row;
        row.wi = wi;
        row.wo = wo;
        row.value =
            glm::dvec3(uniform(random), uniform(random), uniform(random));
        row.alpha = uniform(random);
        row.s = s;
        row.t = t;
        table.rows.push_back(row);
      }
    }
  }
  return table;
}

// Every image of a stack rewritten as a tiled EXR with tiles of `tile`
// pixels (the writer's EXRs are scanline files).
void RetileStack(const std::string& manifest, int tile) {
  ImageStackReader reader(manifest);
  for (size_t k = 0; k < reader.images(); ++k) {
    const std::string path = reader.ImagePath(k);
    auto in = OIIO::ImageInput::open(path);
    ASSERT_TRUE(in) << path;
    OIIO::ImageSpec spec = in->spec();
    std::vector<float> pixels(spec.image_pixels() * spec.nchannels);
    ASSERT_TRUE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT,
                               pixels.data()));
    in->close();
    spec.tile_width = tile;
    spec.tile_height = tile;
    spec.set_format(OIIO::TypeDesc::FLOAT);
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out && out->open(path, spec)) << path;
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()));
    out->close();
  }
}

// A region of a stack reads the rows of a whole read inside it, s and t
// from the region's corner: from scanline and tiled EXR (the region across
// tile borders, and at the image's edge where the tiles are partial) and
// PNG.
TEST(ImageRegionTest, RegionReadsThePixelsOfTheWholeRead) {
  const fs::path dir = TestDir();
  const MeasurementTable table = Stack(3, 10, 7);
  for (const std::string ext : {"exr", "tiled", "png"}) {
    const std::string manifest = (dir / (ext + ".csv")).string();
    WriteImageStack(table, manifest, ext == "png" ? ".png" : ".exr", true);
    if (ext == "tiled") RetileStack(manifest, 4);
    const MeasurementTable whole = ReadImageStack(manifest);
    for (const PixelRegion& region :
         {PixelRegion{2, 1, 4, 4}, PixelRegion{6, 3, 4, 4},
          PixelRegion{0, 0, 10, 7}, PixelRegion{9, 6, 1, 1}}) {
      ReadStackOptions options;
      options.region = region;
      const MeasurementTable part = ReadImageStack(manifest, options);
      ASSERT_EQ(part.rows.size(), 3u * region.width * region.height) << ext;
      size_t i = 0;
      for (int k = 0; k < 3; ++k) {
        for (int y = 0; y < region.height; ++y) {
          for (int x = 0; x < region.width; ++x) {
            const TableRow& row = part.rows[i++];
            const TableRow& full =
                whole.rows[(k * 7 + region.y + y) * 10 + region.x + x];
            EXPECT_EQ(row.s, x);
            EXPECT_EQ(row.t, y);
            EXPECT_EQ(row.value, full.value) << ext << " image " << k;
            EXPECT_EQ(row.alpha, full.alpha) << ext;
            EXPECT_EQ(row.wi, full.wi);
            EXPECT_EQ(row.source_line, full.source_line);
          }
        }
      }
    }
    ReadStackOptions outside;
    outside.region = PixelRegion{8, 0, 4, 4};
    ExpectHas(ErrorOf([&] { ReadImageStack(manifest, outside); }),
              {"region 8,0,4,4 is not inside the image of 10 x 7"});
  }
}

}  // namespace
}  // namespace clothfit
