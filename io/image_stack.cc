#include "io/image_stack.h"

#include <OpenImageIO/imageio.h>
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
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
#include "io/input_error.h"
#include "io/oiio_messages.h"
#include "io/text_util.h"
#include "models/math.h"

namespace clothfit {
namespace {

namespace fs = std::filesystem;

using text_util::FormatNumber;
using text_util::Lower;
using text_util::OneLine;
using text_util::Quote;
using text_util::SplitFields;
using text_util::Trim;

// Largest image accepted (pixels), against corrupt headers.
constexpr int64_t kMaxPixels = int64_t{1} << 28;

constexpr std::array<const char*, 10> kDirectionColumns = {
    "theta_i", "phi_i", "theta_o", "phi_o", "wi_x",
    "wi_y",    "wi_z",  "wo_x",    "wo_y",  "wo_z"};

// The manifest's metadata key naming the per-texel normal image.
constexpr const char* kNormalMapKey = "normal_map";

// Distinguishes temporary files of concurrent writers within one process.
std::atomic<unsigned> temp_counter{0};

[[noreturn]] void Fail(const std::string& file, int line, int column,
                       const std::string& problem) {
  throw InputError(FormatLocation(file, line, column) + ": " + problem);
}

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
  std::error_code error;
  if (!fs::exists(path, error)) {
    Fail(path, 0, 0,
         std::string("cannot read image: ") + std::strerror(ENOENT) + listed);
  }
  if (fs::is_directory(path, error)) {
    Fail(path, 0, 0,
         std::string("cannot read image: ") + std::strerror(EISDIR) + listed);
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
  return image;
}

bool UsesFloat(const std::string& extension) {
  const std::string ext = Lower(extension);
  return ext == ".exr" || ext == ".tif" || ext == ".tiff" || ext == ".pfm" ||
         ext == ".hdr";
}

}  // namespace

void WriteImage(const std::string& path, int width, int height,
                int colour_channels, bool with_alpha, bool float_pixels,
                const std::vector<float>& pixels) {
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

  // A temporary name beside the target; the format was chosen above from
  // the target's extension.
  std::string temp;
  for (int attempt = 0; attempt < 100 && temp.empty(); ++attempt) {
    const std::string candidate = path + ".tmp-" + std::to_string(::getpid()) +
                                  "-" +
                                  std::to_string(temp_counter.fetch_add(1));
    const int fd = ::open(candidate.c_str(),
                          O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd >= 0) {
      ::close(fd);
      temp = candidate;
    } else if (errno != EEXIST) {
      Fail(path, 0, 0, std::string("cannot write: ") + std::strerror(errno));
    }
  }
  if (temp.empty()) {
    Fail(path, 0, 0, std::string("cannot write: ") + std::strerror(EEXIST));
  }
  std::string problem;
  if (!out->open(temp, spec) ||
      !out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()) ||
      !out->close()) {
    problem = "cannot write image: " + OneLineMessage(out->geterror());
  } else if (std::rename(temp.c_str(), path.c_str()) != 0) {
    problem = std::string("cannot write: ") + std::strerror(errno);
  }
  if (!problem.empty()) {
    out.reset();
    ::unlink(temp.c_str());
    Fail(path, 0, 0, problem);
  }
}

namespace {

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
                pair, theta_i * kDegreesPerRadian, phi_i * kDegreesPerRadian,
                theta_o * kDegreesPerRadian, phi_o * kDegreesPerRadian);
  return buffer;
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
    WriteImage((folder.empty() ? fs::path(file) : folder / file).string(),
               width, height, 3, false, float_pixels, pixels);
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
    } catch (const InputError&) {
      throw;
    } catch (const std::exception& error) {
      Fail(path, 0, 0, std::string("cannot write image: ") + error.what());
    }

    const TableRow& row = table.rows[first_row[pair]];
    double theta_i = 0.0, phi_i = 0.0, theta_o = 0.0, phi_o = 0.0;
    AnglesFromDirection(row.wi, &theta_i, &phi_i);
    AnglesFromDirection(row.wo, &theta_o, &phi_o);
    text += FormatNumber(theta_i * kDegreesPerRadian) + "," +
            FormatNumber(phi_i * kDegreesPerRadian) + "," +
            FormatNumber(theta_o * kDegreesPerRadian) + "," +
            FormatNumber(phi_o * kDegreesPerRadian) + "," + file + "\n";
  }
  WriteFileAtomically(manifest_path, text);
}

}  // namespace clothfit
