#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <map>
#include <memory>
#include <new>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "io/atomic_file.h"
#include "io/image_guard.h"
#include "io/image_stack.h"
#include "io/image_stack_internal.h"
#include "io/input_error.h"
#include "io/oiio_messages.h"
#include "io/text_util.h"
#include "models/math.h"

namespace clothfit {
namespace {

using image_stack_internal::Fail;
using image_stack_internal::kMaxPixels;
using image_stack_internal::kNormalMapKey;
namespace fs = std::filesystem;

using text_util::FormatNumber;
using text_util::Lower;
using text_util::OneLine;
using text_util::Trim;

bool UsesFloat(const std::string& extension) {
  const std::string ext = Lower(extension);
  return ext == ".exr" || ext == ".tif" || ext == ".tiff" || ext == ".pfm" ||
         ext == ".hdr";
}

using DirectionKey = std::array<double, 6>;

DirectionKey KeyOf(const TableRow& row) {
  return {row.wi.x, row.wi.y, row.wi.z, row.wo.x, row.wo.y, row.wo.z};
}

std::string PairLabel(size_t pair, const TableRow& row) {
  double theta_i = 0.0, phi_i = 0.0, theta_o = 0.0, phi_o = 0.0;
  AnglesFromDirection(row.wi, &theta_i, &phi_i);
  AnglesFromDirection(row.wo, &theta_o, &phi_o);
  char buffer[160];
  std::snprintf(buffer, sizeof(buffer),
                "direction pair %zu (theta_i %.6g, phi_i %.6g, theta_o %.6g, "
                "phi_o %.6g degrees)",
                pair, Degrees(theta_i), Degrees(phi_i), Degrees(theta_o),
                Degrees(phi_o));
  return buffer;
}

}  // namespace

void WriteImage(
    const std::string& path, int width, int height, int colour_channels,
    bool with_alpha, bool float_pixels, const std::vector<float>& pixels,
    const std::vector<std::pair<std::string, std::string>>& attributes) {
  // No image holds a NaN or infinity: a renderer would show it as black or
  // as a firefly, and clothfit's readers refuse it.
  const int stride = colour_channels + (with_alpha ? 1 : 0);
  for (size_t i = 0; i < pixels.size(); ++i) {
    if (std::isfinite(pixels[i])) continue;
    const size_t pixel = i / static_cast<size_t>(std::max(stride, 1));
    const size_t row_length = static_cast<size_t>(std::max(width, 1));
    Fail(path, 0, 0,
         "not written: pixel (" + std::to_string(pixel % row_length) + ", " +
             std::to_string(pixel / row_length) + ") channel " +
             std::to_string(i % stride) + " is " +
             (std::isnan(pixels[i]) ? "NaN" : "infinite") +
             " (the model gives no finite value there)");
  }
  std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create(path);
  if (!out) {
    Fail(path, 0, 0, "cannot write image: " + OneLineMessage(OIIO::geterror()));
  }
  const int channels = colour_channels + (with_alpha ? 1 : 0);
  OIIO::ImageSpec spec(
      width, height, channels,
      float_pixels ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
  if (colour_channels == 1) {
    spec.channelnames = {"Y"};
  } else {
    spec.channelnames = {"R", "G", "B"};
  }
  spec.alpha_channel = -1;
  if (with_alpha) {
    spec.channelnames.push_back("A");
    spec.alpha_channel = colour_channels;
  }
  spec.attribute("oiio:UnassociatedAlpha", 1);
  for (const auto& [name, value] : attributes) spec.attribute(name, value);

  // The format was chosen above from the target's extension; the file is
  // written under a temporary name beside it.
  WriteAtomicallyVia(path, [&](const std::string& temp) -> std::string {
    if (!out->open(temp, spec) ||
        !out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()) ||
        !out->close()) {
      return "cannot write image: " + OneLineMessage(out->geterror());
    }
    return "";
  });
}

void WriteImageStack(const MeasurementTable& table,
                     const std::string& manifest_path,
                     const std::string& extension, bool with_alpha) {
  const std::string& name = manifest_path;
  if (table.rows.empty()) Fail(name, 0, 0, "cannot write an empty stack");
  const std::string ext =
      extension.empty() || extension[0] == '.' ? extension : "." + extension;
  if (ext.size() < 2) Fail(name, 0, 0, "no image file extension given");

  // Direction pairs in order of first appearance, and the grid size.
  std::map<DirectionKey, size_t> pair_of;
  std::vector<size_t> first_row;  // per pair
  std::vector<size_t> row_pair(table.rows.size());
  int width = 0;
  int height = 0;
  for (size_t i = 0; i < table.rows.size(); ++i) {
    const TableRow& row = table.rows[i];
    if (row.s < 0 || row.t < 0) {
      Fail(name, 0, 0,
           "row " + std::to_string(i + 1) +
               " has no texel indices (s, t); an image stack needs them");
    }
    const auto [it, added] = pair_of.emplace(KeyOf(row), first_row.size());
    if (added) first_row.push_back(i);
    row_pair[i] = it->second;
    width = std::max(width, row.s + 1);
    height = std::max(height, row.t + 1);
  }
  const size_t pairs = first_row.size();
  const uint64_t texels = static_cast<uint64_t>(width) * height;
  if (texels > static_cast<uint64_t>(kMaxPixels)) {
    Fail(name, 0, 0,
         "image size " + std::to_string(width) + " x " +
             std::to_string(height) + " is too large");
  }

  // Which row fills each texel of each pair.
  const size_t kNone = static_cast<size_t>(-1);
  std::vector<std::vector<size_t>> grid(pairs);
  for (size_t i = 0; i < table.rows.size(); ++i) {
    const TableRow& row = table.rows[i];
    const size_t pair = row_pair[i];
    std::vector<size_t>& cells = grid[pair];
    if (cells.empty()) cells.assign(texels, kNone);
    size_t& cell = cells[static_cast<size_t>(row.t) * width + row.s];
    if (cell != kNone) {
      Fail(name, 0, 0,
           PairLabel(pair, row) + ": texel (" + std::to_string(row.s) + ", " +
               std::to_string(row.t) + ") given twice (rows " +
               std::to_string(cell + 1) + " and " + std::to_string(i + 1) +
               ")");
    }
    cell = i;
  }
  for (size_t pair = 0; pair < pairs; ++pair) {
    for (size_t cell = 0; cell < texels; ++cell) {
      if (grid[pair][cell] == kNone) {
        Fail(name, 0, 0,
             PairLabel(pair, table.rows[first_row[pair]]) + ": texel (" +
                 std::to_string(cell % width) + ", " +
                 std::to_string(cell / width) + ") is missing; every pair " +
                 "must cover the full " + std::to_string(width) + " x " +
                 std::to_string(height) + " grid");
      }
    }
  }

  // One normal per texel: every pair's row of a texel must agree.
  std::vector<glm::dvec3> normals;
  if (table.has_normal) {
    normals.resize(texels);
    for (size_t cell = 0; cell < texels; ++cell) {
      const size_t first = grid[0][cell];
      normals[cell] = table.rows[first].normal;
      for (size_t pair = 1; pair < pairs; ++pair) {
        const size_t other = grid[pair][cell];
        if (glm::length(table.rows[other].normal - normals[cell]) > 1e-9) {
          Fail(name, 0, 0,
               "texel (" + std::to_string(cell % width) + ", " +
                   std::to_string(cell / width) + ") has different normals " +
                   "in rows " + std::to_string(first + 1) + " and " +
                   std::to_string(other + 1) +
                   "; an image stack holds one normal per texel");
        }
      }
    }
  }

  const fs::path manifest(manifest_path);
  const std::string stem = manifest.stem().string();
  if (stem.empty() || stem.find_first_of(",\n\r") != std::string::npos) {
    Fail(name, 0, 0,
         "the manifest's name must be non-empty and hold no ',' or line "
         "breaks (it names the images)");
  }
  const fs::path folder = manifest.parent_path();
  const bool float_pixels = UsesFloat(ext);
  const int colour_channels = table.channels == 1 ? 1 : 3;
  const int channels = colour_channels + (with_alpha ? 1 : 0);

  // The images written so far, removed again when a later one or the
  // manifest cannot be written (a full disk): a failed run leaves no part
  // of a stack.
  struct Written {
    std::vector<std::string> paths;
    bool complete = false;
    ~Written() {
      std::error_code error;
      for (const std::string& path : paths) {
        if (!complete) fs::remove(path, error);
      }
    }
  } written;

  std::string text = "# clothfit-stack 1\n";
  text += std::string("# quantity: ") + QuantityName(table.quantity) + "\n";
  text += "# units: degrees\n";
  if (!normals.empty()) {
    // The normal map: raw in a float image, 0.5 (n + 1) in an 8-bit one.
    const std::string file = stem + "_normal" + ext;
    std::vector<float> pixels;
    pixels.reserve(texels * 3);
    for (const glm::dvec3& n : normals) {
      for (int c = 0; c < 3; ++c) {
        pixels.push_back(
            static_cast<float>(float_pixels ? n[c] : 0.5 * (n[c] + 1.0)));
      }
    }
    const std::string path =
        (folder.empty() ? fs::path(file) : folder / file).string();
    WriteImage(path, width, height, 3, false, float_pixels, pixels);
    written.paths.push_back(path);  // only what this run replaced
    text += std::string("# ") + kNormalMapKey + ": " + file + "\n";
  }
  for (const auto& [key, value] : table.metadata) {
    std::string key_name = Lower(Trim(OneLine(key)));
    std::replace(key_name.begin(), key_name.end(), ':', '_');
    if (key_name.empty() || key_name == "quantity" || key_name == "units" ||
        key_name == "clothfit-table" || key_name == "clothfit-stack" ||
        key_name == kNormalMapKey) {
      continue;
    }
    text += "# " + key_name + ": " + OneLine(value) + "\n";
  }
  text += "theta_i,phi_i,theta_o,phi_o,file\n";

  std::vector<float> pixels(texels * channels);
  for (size_t pair = 0; pair < pairs; ++pair) {
    char suffix[32];
    std::snprintf(suffix, sizeof(suffix), "_%04zu", pair);
    const std::string file = stem + suffix + ext;
    const std::string path =
        (folder.empty() ? fs::path(file) : folder / file).string();
    for (size_t cell = 0; cell < texels; ++cell) {
      const TableRow& row = table.rows[grid[pair][cell]];
      float* pixel = pixels.data() + cell * channels;
      std::array<double, 4> values = {row.value.x, row.value.y, row.value.z,
                                      row.alpha};
      if (colour_channels == 1) values[1] = row.alpha;
      for (int c = 0; c < channels; ++c) {
        double v = values[c];
        if (!float_pixels) v = std::isnan(v) ? 0.0 : std::clamp(v, 0.0, 1.0);
        pixel[c] = static_cast<float>(v);
      }
    }
    try {
      WriteImage(path, width, height, colour_channels, with_alpha, float_pixels,
                 pixels);
      written.paths.push_back(path);
    } catch (const InputError&) {
      throw;
    } catch (const std::exception& error) {
      Fail(path, 0, 0, std::string("cannot write image: ") + error.what());
    }

    const TableRow& row = table.rows[first_row[pair]];
    double theta_i = 0.0, phi_i = 0.0, theta_o = 0.0, phi_o = 0.0;
    AnglesFromDirection(row.wi, &theta_i, &phi_i);
    AnglesFromDirection(row.wo, &theta_o, &phi_o);
    text += FormatNumber(Degrees(theta_i)) + "," +
            FormatNumber(Degrees(phi_i)) + "," +
            FormatNumber(Degrees(theta_o)) + "," +
            FormatNumber(Degrees(phi_o)) + "," + file + "\n";
  }
  WriteFileAtomically(manifest_path, text);
  written.complete = true;
}

}  // namespace clothfit
