#include "io/image_stack.h"

#include <OpenImageIO/imageio.h>
#include <fcntl.h>
#include <unistd.h>

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
#include "io/image_stack_internal.h"
#include "io/input_error.h"
#include "io/oiio_messages.h"
#include "io/text_util.h"
#include "models/math.h"

namespace clothfit {
namespace {

using image_stack_internal::Fail;
using image_stack_internal::kMaxPixels;

// Most rows a stack may make (a row is sizeof(TableRow), ~150 bytes).
constexpr int64_t kMaxStackRows = int64_t{1} << 25;
using image_stack_internal::kNormalMapKey;
namespace fs = std::filesystem;

using text_util::FormatNumber;
using text_util::Lower;
using text_util::Quote;
using text_util::SplitFields;
using text_util::Trim;

constexpr std::array<const char*, 10> kDirectionColumns = {
    "theta_i", "phi_i", "theta_o", "phi_o", "wi_x",
    "wi_y",    "wi_z",  "wo_x",    "wo_y",  "wo_z"};

// One image of the manifest.
struct StackEntry {
  glm::dvec3 wi, wo;
  std::string file;  // as written in the manifest
  int line = 0;
};

struct Manifest {
  MeasurementTable table;  // metadata, quantity, direction columns; no rows
  std::vector<StackEntry> entries;
  std::string normal_map;  // "# normal_map: FILE", as written; empty: none
  int normal_map_line = 0;
};

// Parses a manifest. The `file` column is taken out here; the rest (metadata,
// direction columns, numbers, ranges) is checked by the table parser, with
// the file column standing in as a constant 'weight' column so that line and
// column numbers in its messages stay those of the manifest.
Manifest ParseManifest(std::string_view text, const std::string& name) {
  std::string_view body = text;
  if (body.substr(0, 3) == "\xEF\xBB\xBF") body.remove_prefix(3);

  std::string substitute;
  substitute.reserve(body.size() + 16);
  int line = 0;
  int header_line = 0;
  size_t header_fields = 0;
  size_t file_field = 0;
  std::map<int, std::string> files;  // line -> file name
  std::string normal_map;
  int normal_map_line = 0;
  size_t start = 0;
  while (start <= body.size()) {
    size_t end = body.find('\n', start);
    if (end == std::string_view::npos) end = body.size();
    std::string_view content = body.substr(start, end - start);
    start = end + 1;
    ++line;
    if (!content.empty() && content.back() == '\r') content.remove_suffix(1);
    const std::string_view trimmed = Trim(content);
    if (!trimmed.empty() && trimmed.front() == '#' && header_line == 0) {
      const auto version =
          text_util::FormatVersion(trimmed.substr(1), "clothfit-stack");
      if (version && *version != "1") {
        Fail(name, line, 0,
             "unsupported manifest format version " + Quote(*version) +
                 " (this clothfit reads '# clothfit-stack 1')");
      }
    }
    if (trimmed.empty() || trimmed.front() == '#') {
      // Before the header, '#' lines are metadata (as in a table); the
      // table parser reads all but normal_map, which names a file.
      const size_t colon = trimmed.find(':');
      if (header_line == 0 && !trimmed.empty() &&
          colon != std::string_view::npos &&
          Lower(Trim(trimmed.substr(1, colon - 1))) == kNormalMapKey) {
        if (normal_map_line > 0) {
          Fail(name, line, 0,
               std::string("metadata '") + kNormalMapKey +
                   "': given again (first on line " +
                   std::to_string(normal_map_line) + ")");
        }
        normal_map = Trim(trimmed.substr(colon + 1));
        normal_map_line = line;
        if (normal_map.empty()) {
          Fail(
              name, line, 0,
              std::string("metadata '") + kNormalMapKey + "': empty file name");
        }
        substitute += '\n';  // keeps the line numbers
        continue;
      }
      substitute.append(content);
      substitute += '\n';
      continue;
    }
    const std::vector<std::string_view> fields = SplitFields(content);
    if (header_line == 0) {
      header_line = line;
      header_fields = fields.size();
      bool found = false;
      for (size_t i = 0; i < fields.size(); ++i) {
        const int column = static_cast<int>(i) + 1;
        const std::string column_name = Lower(Trim(fields[i]));
        if (column_name.empty()) Fail(name, line, column, "empty column name");
        if (column_name == "file") {
          if (found) {
            Fail(name, line, column,
                 "duplicate column 'file' (first at column " +
                     std::to_string(file_field + 1) + ")");
          }
          found = true;
          file_field = i;
        } else if (std::find(kDirectionColumns.begin(), kDirectionColumns.end(),
                             column_name) == kDirectionColumns.end()) {
          Fail(name, line, column,
               "unknown column " + Quote(column_name) +
                   " (expected theta_i,phi_i,theta_o,phi_o or "
                   "wi_x,wi_y,wi_z,wo_x,wo_y,wo_z, and file)");
        }
      }
      if (!found) Fail(name, line, 0, "missing column 'file'");
    } else {
      if (fields.size() != header_fields) {
        const int column =
            static_cast<int>(std::min(fields.size(), header_fields)) + 1;
        Fail(name, line, column,
             "row has " + std::to_string(fields.size()) +
                 " fields, header has " + std::to_string(header_fields));
      }
      const std::string file(Trim(fields[file_field]));
      if (file.empty()) {
        Fail(name, line, static_cast<int>(file_field) + 1,
             "column 'file': empty file name");
      }
      files[line] = file;
    }
    // The same line with the file field replaced.
    for (size_t i = 0; i < fields.size(); ++i) {
      if (i > 0) substitute += ',';
      if (i != file_field) {
        substitute.append(fields[i]);
      } else {
        substitute += header_line == line ? "weight" : "0";
      }
    }
    substitute += '\n';
  }
  if (header_line == 0) {
    Fail(name, 0, 0,
         "no header (expected a line of column names such as "
         "theta_i,phi_i,theta_o,phi_o,file)");
  }
  if (files.empty()) Fail(name, header_line, 0, "manifest lists no images");

  ReadTableOptions options;
  options.values_optional = true;
  ReadTableResult parsed = ParseTable(substitute, name, options);
  Manifest manifest;
  manifest.table = std::move(parsed.table);
  for (const TableRow& row : manifest.table.rows) {
    StackEntry entry;
    entry.wi = row.wi;
    entry.wo = row.wo;
    entry.line = row.source_line;
    entry.file = files.at(row.source_line);
    manifest.entries.push_back(std::move(entry));
  }
  manifest.table.rows.clear();
  manifest.table.has_weight = false;
  manifest.normal_map = std::move(normal_map);
  manifest.normal_map_line = normal_map_line;
  return manifest;
}

// Pixels of one image, as floats.
struct Image {
  int width = 0, height = 0, channels = 0;
  int alpha = -1;               // alpha channel index, -1 when none
  std::vector<int> colour;      // 1 (grey) or 3 (r, g, b) indices
  std::vector<float> pixels;    // channels per pixel, row-major
  bool integer_pixels = false;  // stored as integers (read scaled to [0, 1])
};

Image ReadImage(const std::string& path, const std::string& manifest,
                int line) {
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
  image.pixels.resize(static_cast<size_t>(image.width) * image.height *
                      image.channels);
  if (!Quietly([&] {
        return in->read_image(0, 0, 0, image.channels, OIIO::TypeDesc::FLOAT,
                              image.pixels.data());
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
         "pixel (" + std::to_string(pixel % image.width) + ", " +
             std::to_string(pixel / image.width) + ") channel " +
             std::to_string(i % image.channels) + " is " +
             (std::isnan(image.pixels[i]) ? "NaN" : "infinite") +
             " (a measurement is a finite number)" + listed);
  }
  return image;
}

// ReadImage with every failure as an InputError naming the image.
Image ReadListedImage(const std::string& path, const std::string& manifest,
                      int line) {
  try {
    return ReadImage(path, manifest, line);
  } catch (const InputError&) {
    throw;
  } catch (const std::bad_alloc&) {
    Fail(path, 0, 0, "out of memory reading the image");
  } catch (const std::exception& error) {
    Fail(path, 0, 0, std::string("cannot read image: ") + error.what());
  }
}

// The unit normal of every pixel of a normal map: (x, y, z) in the surface
// frame from its three colour channels, stored as they are in a float image
// and as 2 v - 1 (v in [0, 1]) in an integer one; alpha is ignored.
std::vector<glm::dvec3> NormalsOf(const Image& image, const std::string& path,
                                  const std::string& manifest, int line) {
  const std::string listed =
      " (normal map of " + FormatLocation(manifest, line, 0) + ")";
  if (image.colour.size() != 3) {
    Fail(path, 0, 0,
         "a normal map needs 3 colour channels (x, y, z), got " +
             std::to_string(image.colour.size()) + listed);
  }
  std::vector<glm::dvec3> normals;
  normals.reserve(static_cast<size_t>(image.width) * image.height);
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const float* pixel =
          image.pixels.data() +
          (static_cast<size_t>(y) * image.width + x) * image.channels;
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
        std::snprintf(where, sizeof(where), "pixel (%d, %d): ", x, y);
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

}  // namespace

MeasurementTable ReadImageStack(const std::string& manifest_path,
                                const ReadStackOptions& options) {
  if (options.stride < 1) {
    Fail(manifest_path, 0, 0,
         "stride must be at least 1, got " + std::to_string(options.stride));
  }
  Manifest manifest =
      ParseManifest(ReadFileToString(manifest_path), manifest_path);
  MeasurementTable table = std::move(manifest.table);
  table.source = manifest_path;
  table.has_texels = true;
  table.has_sigma = false;
  table.has_weight = false;
  table.has_alpha = false;
  table.channels = 1;

  const fs::path folder = fs::path(manifest_path).parent_path();
  auto resolve = [&folder](const std::string& name) {
    const fs::path file(name);
    return (file.is_absolute() || folder.empty() ? file : folder / file)
        .string();
  };
  const int stride = options.stride;
  int width = 0;
  int height = 0;
  std::string first_image;
  std::vector<glm::dvec3> normals;  // per pixel, from the normal map
  if (!manifest.normal_map.empty()) {
    first_image = resolve(manifest.normal_map);
    if (options.images != nullptr) options.images->push_back(first_image);
    const Image image =
        ReadListedImage(first_image, manifest_path, manifest.normal_map_line);
    width = image.width;
    height = image.height;
    normals =
        NormalsOf(image, first_image, manifest_path, manifest.normal_map_line);
    table.has_normal = true;
  }
  for (const StackEntry& entry : manifest.entries) {
    const std::string path = resolve(entry.file);
    if (options.images != nullptr) options.images->push_back(path);
    const Image image = ReadListedImage(path, manifest_path, entry.line);
    if (first_image.empty()) {
      width = image.width;
      height = image.height;
      first_image = path;
    } else if (image.width != width || image.height != height) {
      Fail(path, 0, 0,
           "image is " + std::to_string(image.width) + " x " +
               std::to_string(image.height) + ", but " + first_image + " is " +
               std::to_string(width) + " x " + std::to_string(height) +
               " (listed on " + FormatLocation(manifest_path, entry.line, 0) +
               ")");
    }
    if (image.colour.size() == 3) table.channels = 3;
    if (image.alpha >= 0) table.has_alpha = true;
    if (table.rows.empty()) {
      // The rows the whole stack makes, before they are made: images of
      // a size one may read can still add up to more than the memory.
      const int64_t per_image = ((int64_t{width} + stride - 1) / stride) *
                                ((int64_t{height} + stride - 1) / stride);
      const int64_t rows =
          per_image * static_cast<int64_t>(manifest.entries.size());
      if (rows > kMaxStackRows) {
        Fail(manifest_path, 0, 0,
             std::to_string(manifest.entries.size()) + " images of " +
                 std::to_string(width) + " x " + std::to_string(height) +
                 " texels make " + std::to_string(rows) + " rows, more than " +
                 std::to_string(kMaxStackRows) + " (about " +
                 std::to_string(kMaxStackRows * sizeof(TableRow) >> 30) +
                 " GB); fit smaller images or fewer directions");
      }
      table.rows.reserve(static_cast<size_t>(rows));
    }

    for (int y = 0; y < height; y += stride) {
      for (int x = 0; x < width; x += stride) {
        const size_t texel = static_cast<size_t>(y) * width + x;
        const float* pixel = image.pixels.data() + texel * image.channels;
        TableRow row;
        row.wi = entry.wi;
        row.wo = entry.wo;
        if (image.colour.size() == 1) {
          row.value = glm::dvec3(pixel[image.colour[0]]);
        } else {
          row.value = glm::dvec3(pixel[image.colour[0]], pixel[image.colour[1]],
                                 pixel[image.colour[2]]);
        }
        if (image.alpha >= 0) row.alpha = pixel[image.alpha];
        if (!normals.empty()) row.normal = normals[texel];
        row.s = x;
        row.t = y;
        row.source_line = entry.line;
        table.rows.push_back(row);
      }
    }
  }
  return table;
}

}  // namespace clothfit
