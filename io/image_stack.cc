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
using image_stack_internal::Image;
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

}  // namespace

struct ImageStackReader::State {
  std::string manifest_path;
  Manifest manifest;
  MeasurementTable directions;
  fs::path folder;
  int width = 0, height = 0;
  std::string first_image;  // the image whose size the others must have
  // The normals of the last region read of the normal map.
  PixelRegion normals_region{-1, -1, -1, -1};
  std::vector<glm::dvec3> normals;

  std::string Resolve(const std::string& name) const {
    const fs::path file(name);
    return (file.is_absolute() || folder.empty() ? file : folder / file)
        .string();
  }
};

ImageStackReader::ImageStackReader(const std::string& manifest_path)
    : state_(std::make_unique<State>()) {
  State& s = *state_;
  s.manifest_path = manifest_path;
  s.manifest = ParseManifest(ReadFileToString(manifest_path), manifest_path);
  MeasurementTable& table = s.manifest.table;
  table.source = manifest_path;
  table.has_texels = true;
  table.has_sigma = false;
  table.has_weight = false;
  table.has_alpha = false;
  table.has_normal = !s.manifest.normal_map.empty();
  table.channels = 1;
  s.folder = fs::path(manifest_path).parent_path();
  s.directions = table;
  for (const StackEntry& entry : s.manifest.entries) {
    TableRow row;
    row.wi = entry.wi;
    row.wo = entry.wo;
    row.source_line = entry.line;
    s.directions.rows.push_back(row);
  }
  // The size every image must have: the first's, read from a region of
  // one pixel.
  const bool normal_map = table.has_normal;
  s.first_image = normal_map ? s.Resolve(s.manifest.normal_map)
                             : s.Resolve(s.manifest.entries.front().file);
  const Image first = image_stack_internal::ReadStackImage(
      s.first_image, manifest_path,
      normal_map ? s.manifest.normal_map_line : s.manifest.entries.front().line,
      PixelRegion{0, 0, 1, 1});
  s.width = first.width;
  s.height = first.height;
}

ImageStackReader::~ImageStackReader() = default;

const MeasurementTable& ImageStackReader::header() const {
  return state_->manifest.table;
}
const MeasurementTable& ImageStackReader::directions() const {
  return state_->directions;
}
size_t ImageStackReader::images() const {
  return state_->manifest.entries.size();
}
int ImageStackReader::width() const { return state_->width; }
int ImageStackReader::height() const { return state_->height; }
std::string ImageStackReader::ImagePath(size_t k) const {
  return state_->Resolve(state_->manifest.entries.at(k).file);
}
std::string ImageStackReader::NormalMapPath() const {
  return state_->manifest.normal_map.empty()
             ? ""
             : state_->Resolve(state_->manifest.normal_map);
}

void ImageStackReader::AppendRows(size_t k, const PixelRegion& region,
                                  int stride, bool local,
                                  MeasurementTable* table) {
  State& s = *state_;
  const StackEntry& entry = s.manifest.entries.at(k);
  const std::string path = ImagePath(k);
  if (header().has_normal &&
      (s.normals_region.x != region.x || s.normals_region.y != region.y ||
       s.normals_region.width != region.width ||
       s.normals_region.height != region.height)) {
    const Image map = image_stack_internal::ReadStackImage(
        s.first_image, s.manifest_path, s.manifest.normal_map_line, region);
    s.normals = image_stack_internal::NormalsOf(
        map, s.first_image, s.manifest_path, s.manifest.normal_map_line);
    s.normals_region = region;
  }
  const Image image = image_stack_internal::ReadStackImage(
      path, s.manifest_path, entry.line, region,
      {s.width, s.height, s.first_image});
  if (image.colour.size() == 3) table->channels = 3;
  if (image.alpha >= 0) table->has_alpha = true;
  const PixelRegion& r = image.region;
  for (int y = 0; y < r.height; y += stride) {
    for (int x = 0; x < r.width; x += stride) {
      const size_t texel = static_cast<size_t>(y) * r.width + x;
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
      if (!s.normals.empty() && header().has_normal) {
        row.normal = s.normals[texel];
      }
      row.s = local ? x : r.x + x;
      row.t = local ? y : r.y + y;
      row.source_line = entry.line;
      table->rows.push_back(row);
    }
  }
}

MeasurementTable ReadImageStack(const std::string& manifest_path,
                                const ReadStackOptions& options) {
  if (options.stride < 1) {
    Fail(manifest_path, 0, 0,
         "stride must be at least 1, got " + std::to_string(options.stride));
  }
  ImageStackReader reader(manifest_path);
  MeasurementTable table = reader.header();
  if (options.images != nullptr) {
    if (table.has_normal) options.images->push_back(reader.NormalMapPath());
    for (size_t k = 0; k < reader.images(); ++k) {
      options.images->push_back(reader.ImagePath(k));
    }
  }
  PixelRegion region = options.region;
  if (region.width == 0) region = {0, 0, reader.width(), reader.height()};
  const int stride = options.stride;
  // The rows the whole stack makes, before they are made: images of a size
  // one may read can still add up to more than the memory.
  const int64_t per_image = ((int64_t{region.width} + stride - 1) / stride) *
                            ((int64_t{region.height} + stride - 1) / stride);
  const int64_t rows = per_image * static_cast<int64_t>(reader.images());
  if (rows > kMaxStackRows) {
    Fail(manifest_path, 0, 0,
         std::to_string(reader.images()) + " images of " +
             std::to_string(region.width) + " x " +
             std::to_string(region.height) + " texels make " +
             std::to_string(rows) + " rows, more than " +
             std::to_string(kMaxStackRows) + " (about " +
             std::to_string(kMaxStackRows * sizeof(TableRow) >> 30) +
             " GB); fit smaller images or fewer directions (or a region: "
             "fit --region, docs/scale.md)");
  }
  table.rows.reserve(static_cast<size_t>(rows));
  const bool local = options.region.width != 0;
  for (size_t k = 0; k < reader.images(); ++k) {
    reader.AppendRows(k, region, stride, local, &table);
  }
  return table;
}

}  // namespace clothfit
