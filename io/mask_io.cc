#include "io/mask_io.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <memory>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "io/atomic_file.h"
#include "io/image_guard.h"
#include "io/input_error.h"
#include "io/oiio_messages.h"

namespace clothfit {
namespace {

// Texels reserved for the mask up front (more as rows are read).
constexpr int64_t kReservedTexels = int64_t{1} << 20;

[[noreturn]] void Fail(const std::string& path, const std::string& problem) {
  throw InputError(path + ": " + problem);
}

}  // namespace

double Mask::OpaqueFraction() const {
  if (opaque.empty()) return 0.0;
  size_t count = 0;
  for (uint8_t v : opaque) count += v != 0;
  return static_cast<double>(count) / static_cast<double>(opaque.size());
}

const char* MaskSourceName(MaskSource source) {
  switch (source) {
    case MaskSource::kAlpha:
      return "alpha";
    case MaskSource::kLuminance:
      return "luminance";
    case MaskSource::kAuto:
      break;
  }
  return "auto";
}

Mask ReadMask(const std::string& path, const MaskReadOptions& options) {
  if (!(options.threshold > 0.0 && options.threshold <= 1.0)) {
    Fail(path, "mask threshold must be in (0, 1], got " +
                   std::to_string(options.threshold));
  }
  const std::string file_problem = RegularFileProblem(path);
  if (!file_problem.empty()) Fail(path, "cannot read mask: " + file_problem);
  const std::string header_problem = CheckImageHeader(path, kMaxMaskTexels);
  if (!header_problem.empty())
    Fail(path, "cannot read mask image: " + header_problem);
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);  // values as stored
  std::unique_ptr<OIIO::ImageInput> in =
      Quietly([&] { return OIIO::ImageInput::open(path, &config); });
  if (!in) {
    Fail(path, "cannot read mask image: " + OneLineMessage(OIIO::geterror()));
  }
  const OIIO::ImageSpec& spec = in->spec();
  const int64_t width = spec.width, height = spec.height;
  if (width < 1 || height < 1 || spec.depth > 1 ||
      width * height > kMaxMaskTexels) {
    Fail(path, "unsupported mask size " + std::to_string(width) + " x " +
                   std::to_string(height) + " (at most " +
                   std::to_string(kMaxMaskTexels) + " texels)");
  }
  const int channels = spec.nchannels;
  if (channels < 1) Fail(path, "mask image has no channels");
  int alpha = spec.alpha_channel;
  if (alpha < 0 && (channels == 2 || channels == 4)) alpha = channels - 1;
  const bool use_alpha = alpha >= 0 && options.source != MaskSource::kLuminance;
  if (options.source == MaskSource::kAlpha && alpha < 0) {
    Fail(path, "mask image has no alpha channel (" + std::to_string(channels) +
                   " channels); use the luminance");
  }
  std::vector<int> colour;  // the channels other than alpha
  for (int c = 0; c < channels; ++c) {
    if (c != alpha) colour.push_back(c);
  }
  if (!use_alpha && colour.empty()) {
    Fail(path, "mask image has only an alpha channel; read the alpha");
  }
  Mask mask;
  mask.width = static_cast<int>(width);
  mask.height = static_cast<int>(height);
  // Row by row, so that the float pixels never take more than a row's
  // memory and a header that claims a huge image in a short (truncated or
  // corrupt) file fails at its first missing row, not after allocating for
  // the whole claim. OpenImageIO 2.4's read_scanlines allocated a buffer
  // for 256 rows when asked for one: a 102-byte BMP that claims to be
  // 9175044 texels wide made it allocate 7 GB (found by
  // fuzz/mask_target.cc). The mask grows with the rows actually read.
  std::vector<float> pixels(static_cast<size_t>(width) * channels);
  mask.opaque.reserve(
      static_cast<size_t>(std::min(width * height, kReservedTexels)));
  for (int64_t y = 0; y < height; ++y) {
    if (!Quietly([&] {
          return in->read_scanline(static_cast<int>(spec.y + y), 0,
                                   OIIO::TypeDesc::FLOAT, pixels.data());
        })) {
      Fail(path, "cannot read mask image: " + OneLineMessage(in->geterror()));
    }
    const float* p = pixels.data();
    for (int64_t x = 0; x < width; ++x, p += channels) {
      double value = p[use_alpha ? alpha : colour[0]];
      if (!use_alpha && colour.size() >= 3) {
        value = 0.2126 * p[colour[0]] + 0.7152 * p[colour[1]] +
                0.0722 * p[colour[2]];
      }
      if (!std::isfinite(value)) {
        Fail(path, "texel (" + std::to_string(x) + ", " + std::to_string(y) +
                       ") is not a finite number");
      }
      bool opaque =
          use_alpha ? value >= options.threshold : value < options.threshold;
      if (options.invert) opaque = !opaque;
      mask.opaque.push_back(opaque ? 1 : 0);
    }
  }
  in->close();
  return mask;
}

void WriteMask(const Mask& mask, const std::string& path) {
  if (mask.width < 1 || mask.height < 1 ||
      mask.opaque.size() != static_cast<size_t>(mask.width) * mask.height) {
    Fail(path, "cannot write an empty or inconsistent mask");
  }
  const size_t dot = path.find_last_of('.');
  const size_t slash = path.find_last_of('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) {
    Fail(path, "cannot write mask: the file name needs an image extension");
  }
  cv::Mat image(mask.height, mask.width, CV_8U);
  for (int y = 0; y < mask.height; ++y) {
    for (int x = 0; x < mask.width; ++x) {
      image.at<uint8_t>(y, x) =
          mask.opaque[static_cast<size_t>(y) * mask.width + x] ? 0 : 255;
    }
  }
  std::vector<uchar> bytes;
  bool ok = false;
  try {
    ok = cv::imencode(path.substr(dot), image, bytes);
  } catch (const std::exception& e) {
    Fail(path, std::string("cannot write mask: ") + e.what());
  }
  if (!ok) Fail(path, "cannot write mask: unsupported image format");
  WriteFileAtomically(path, std::string(bytes.begin(), bytes.end()));
}

Mask MaskFromRows(const std::vector<std::string>& rows) {
  Mask mask;
  mask.height = static_cast<int>(rows.size());
  mask.width = rows.empty() ? 0 : static_cast<int>(rows[0].size());
  if (mask.width == 0) throw InputError("mask rows: empty mask");
  for (size_t y = 0; y < rows.size(); ++y) {
    if (static_cast<int>(rows[y].size()) != mask.width) {
      throw InputError("mask rows: row " + std::to_string(y) + " has " +
                       std::to_string(rows[y].size()) + " texels, expected " +
                       std::to_string(mask.width));
    }
    for (char c : rows[y]) {
      if (c != '#' && c != '.') {
        throw InputError("mask rows: row " + std::to_string(y) +
                         ": expected '#' (opaque) or '.' (transparent)");
      }
      mask.opaque.push_back(c == '#' ? 1 : 0);
    }
  }
  return mask;
}

}  // namespace clothfit
