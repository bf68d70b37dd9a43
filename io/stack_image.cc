// One image of a stack, or a region of it, read with OpenImageIO
// (io/image_stack_internal.h).
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <memory>
#include <new>
#include <string>
#include <vector>

#include "io/atomic_file.h"
#include "io/image_guard.h"
#include "io/image_stack_internal.h"
#include "io/input_error.h"
#include "io/oiio_messages.h"
#include "io/text_util.h"

namespace clothfit {
namespace image_stack_internal {
namespace {

using text_util::FormatNumber;

// The pixels of `region` (inside the image) in `in`, as floats: a tiled
// file through the tiles the region touches (read_tiles wants whole tiles,
// or the image's last partial ones), a scanline file through its rows.
// Coordinates count from the data window's corner. False on a read error.
bool ReadRegion(OIIO::ImageInput* in, const PixelRegion& r, int channels,
                std::vector<float>* pixels) {
  const OIIO::ImageSpec& spec = in->spec();
  pixels->resize(static_cast<size_t>(r.width) * r.height * channels);
  const size_t row_floats = static_cast<size_t>(r.width) * channels;
  if (spec.tile_width > 0 && spec.tile_height > 0) {
    const int tw = spec.tile_width, th = spec.tile_height;
    const int x0 = r.x / tw * tw, y0 = r.y / th * th;
    const int x1 = std::min(spec.width, (r.x + r.width + tw - 1) / tw * tw);
    const int y1 = std::min(spec.height, (r.y + r.height + th - 1) / th * th);
    std::vector<float> tiles(static_cast<size_t>(x1 - x0) * (y1 - y0) *
                             channels);
    if (!in->read_tiles(0, 0, spec.x + x0, spec.x + x1, spec.y + y0,
                        spec.y + y1, spec.z, spec.z + std::max(1, spec.depth),
                        0, channels, OIIO::TypeDesc::FLOAT, tiles.data())) {
      return false;
    }
    for (int y = 0; y < r.height; ++y) {
      const float* from =
          tiles.data() +
          (static_cast<size_t>(r.y - y0 + y) * (x1 - x0) + (r.x - x0)) *
              channels;
      std::copy(from, from + row_floats, pixels->data() + y * row_floats);
    }
    return true;
  }
  // Scanlines: the region's rows, whole, in one read; its columns kept.
  if (r.x == 0 && r.width == spec.width) {
    return in->read_scanlines(0, 0, spec.y + r.y, spec.y + r.y + r.height,
                              spec.z, 0, channels, OIIO::TypeDesc::FLOAT,
                              pixels->data());
  }
  std::vector<float> rows(static_cast<size_t>(spec.width) * r.height *
                          channels);
  if (!in->read_scanlines(0, 0, spec.y + r.y, spec.y + r.y + r.height, spec.z,
                          0, channels, OIIO::TypeDesc::FLOAT, rows.data())) {
    return false;
  }
  for (int y = 0; y < r.height; ++y) {
    const float* from =
        rows.data() + (static_cast<size_t>(y) * spec.width + r.x) * channels;
    std::copy(from, from + row_floats, pixels->data() + y * row_floats);
  }
  return true;
}

Image ReadImage(const std::string& path, const std::string& manifest, int line,
                const PixelRegion& region, const ExpectedSize& expected) {
  const std::string listed =
      " (listed on " + FormatLocation(manifest, line, 0) + ")";
  const std::string file_problem = RegularFileProblem(path);
  if (!file_problem.empty()) {
    Fail(path, 0, 0, "cannot read image: " + file_problem + listed);
  }
  const std::string header_problem = CheckImageHeader(path, kMaxPixels);
  if (!header_problem.empty()) {
    Fail(path, 0, 0, "cannot read image: " + header_problem + listed);
  }
  OIIO::ImageSpec config;
  // Values as stored: PNG/TIFF colours are not multiplied by alpha.
  config.attribute("oiio:UnassociatedAlpha", 1);
  std::unique_ptr<OIIO::ImageInput> in =
      Quietly([&] { return OIIO::ImageInput::open(path, &config); });
  if (!in) {
    Fail(path, 0, 0,
         "cannot read image: " + OneLineMessage(OIIO::geterror()) + listed);
  }
  const OIIO::ImageSpec& spec = in->spec();
  Image image;
  image.width = spec.width;
  image.height = spec.height;
  image.channels = spec.nchannels;
  image.integer_pixels = !spec.format.is_floating_point();
  if (image.width < 1 || image.height < 1 || spec.depth > 1 ||
      int64_t{image.width} * image.height > kMaxPixels) {
    Fail(path, 0, 0,
         "unsupported image size " + std::to_string(image.width) + " x " +
             std::to_string(image.height) + " x " + std::to_string(spec.depth) +
             listed);
  }
  if (image.channels < 1 || image.channels > 4) {
    Fail(path, 0, 0,
         "image has " + std::to_string(image.channels) +
             " channels, expected 1 (grey), 2 (grey, alpha), 3 (rgb) or 4 "
             "(rgba)" +
             listed);
  }
  if (image.channels == 2 || image.channels == 4) {
    image.alpha = spec.alpha_channel >= 0 && spec.alpha_channel < image.channels
                      ? spec.alpha_channel
                      : image.channels - 1;
  }
  for (int c = 0; c < image.channels; ++c) {
    if (c != image.alpha) image.colour.push_back(c);
  }
  if (expected.width > 0 &&
      (image.width != expected.width || image.height != expected.height)) {
    Fail(path, 0, 0,
         "image is " + std::to_string(image.width) + " x " +
             std::to_string(image.height) + ", but " + expected.image + " is " +
             std::to_string(expected.width) + " x " +
             std::to_string(expected.height) + listed);
  }
  image.region = region;
  if (region.width == 0) {
    image.region = {0, 0, image.width, image.height};
  } else if (region.x < 0 || region.y < 0 || region.width < 1 ||
             region.height < 1 || region.x + region.width > image.width ||
             region.y + region.height > image.height) {
    Fail(path, 0, 0,
         "region " + std::to_string(region.x) + "," + std::to_string(region.y) +
             "," + std::to_string(region.width) + "," +
             std::to_string(region.height) + " is not inside the image of " +
             std::to_string(image.width) + " x " +
             std::to_string(image.height) + listed);
  }
  if (!Quietly([&] {
        return ReadRegion(in.get(), image.region, image.channels,
                          &image.pixels);
      })) {
    Fail(path, 0, 0,
         "cannot read image: " + OneLineMessage(in->geterror()) + listed);
  }
  in->close();
  // A measured value that is not a number (a dead pixel, a failed HDR
  // merge) is the image's fault: named here, not later as a texel's fit.
  for (size_t i = 0; i < image.pixels.size(); ++i) {
    if (std::isfinite(image.pixels[i])) continue;
    const size_t pixel = i / static_cast<size_t>(image.channels);
    Fail(path, 0, 0,
         "pixel (" +
             std::to_string(image.region.x + pixel % image.region.width) +
             ", " +
             std::to_string(image.region.y + pixel / image.region.width) +
             ") channel " + std::to_string(i % image.channels) + " is " +
             (std::isnan(image.pixels[i]) ? "NaN" : "infinite") +
             " (a measurement is a finite number)" + listed);
  }
  return image;
}

}  // namespace

Image ReadStackImage(const std::string& path, const std::string& manifest,
                     int line, const PixelRegion& region,
                     const ExpectedSize& expected) {
  try {
    return ReadImage(path, manifest, line, region, expected);
  } catch (const InputError&) {
    throw;
  } catch (const std::bad_alloc&) {
    Fail(path, 0, 0, "out of memory reading the image");
  } catch (const std::exception& error) {
    Fail(path, 0, 0, std::string("cannot read image: ") + error.what());
  }
}

std::vector<glm::dvec3> NormalsOf(const Image& image, const std::string& path,
                                  const std::string& manifest, int line) {
  const std::string listed =
      " (normal map of " + FormatLocation(manifest, line, 0) + ")";
  if (image.colour.size() != 3) {
    Fail(path, 0, 0,
         "a normal map needs 3 colour channels (x, y, z), got " +
             std::to_string(image.colour.size()) + listed);
  }
  const PixelRegion& r = image.region;
  std::vector<glm::dvec3> normals;
  normals.reserve(static_cast<size_t>(r.width) * r.height);
  for (int y = 0; y < r.height; ++y) {
    for (int x = 0; x < r.width; ++x) {
      const float* pixel =
          image.pixels.data() +
          (static_cast<size_t>(y) * r.width + x) * image.channels;
      glm::dvec3 n(pixel[image.colour[0]], pixel[image.colour[1]],
                   pixel[image.colour[2]]);
      if (image.integer_pixels) n = 2.0 * n - 1.0;
      const bool finite =
          std::isfinite(n.x) && std::isfinite(n.y) && std::isfinite(n.z);
      const double scale =
          finite ? std::max({std::abs(n.x), std::abs(n.y), std::abs(n.z)})
                 : 0.0;
      if (!(scale > 0.0)) {
        char where[64];
        std::snprintf(where, sizeof(where), "pixel (%d, %d): ", r.x + x,
                      r.y + y);
        Fail(path, 0, 0,
             where + std::string(finite ? "zero" : "non-finite") + " normal (" +
                 FormatNumber(n.x) + ", " + FormatNumber(n.y) + ", " +
                 FormatNumber(n.z) + ")" + listed);
      }
      normals.push_back(glm::normalize(n / scale));
    }
  }
  return normals;
}

}  // namespace image_stack_internal
}  // namespace clothfit
