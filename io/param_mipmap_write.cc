#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfStdIO.h>
#include <ImfStringAttribute.h>
#include <ImfTileDescription.h>
#include <ImfTileDescriptionAttribute.h>
#include <ImfTiledOutputFile.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <exception>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "io/atomic_file.h"
#include "io/input_error.h"
#include "io/param_mipmap.h"
#include "io/param_mipmap_internal.h"
#include "models/mip_levels.h"

namespace clothfit {
namespace {

using nlohmann::json;
using param_mipmap_internal::Fail;
using param_mipmap_internal::FirstNonFinite;
using param_mipmap_internal::FirstNonFiniteIn;
using param_mipmap_internal::kFormat;
using param_mipmap_internal::kIndexAttribute;
using param_mipmap_internal::kMaxSide;
using param_mipmap_internal::MakeFrameBuffer;

constexpr int kTileSize = 32;
// Rows of tiles WriteParamMipmapBands fills at a time (64 channels of a
// 4096 texel wide level: 32 MiB of floats).
constexpr int kBandTiles = 1;
// OpenEXR's limit on channel names (with the long-names flag).
constexpr size_t kMaxChannelNameLength = 255;

std::string BaseName(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

// Checks the channel names; `path` is used in messages.
void ValidateChannels(const std::vector<std::string>& channels,
                      const std::string& path) {
  if (channels.empty()) Fail(path, "param mip map has no channels");
  std::set<std::string> names;
  for (const std::string& name : channels) {
    if (name.empty()) Fail(path, "empty channel name");
    if (name.size() > kMaxChannelNameLength ||
        name.find('\0') != std::string::npos) {
      Fail(path, "channel name '" + name.substr(0, 40) +
                     "...' is longer than 255 bytes or holds a NUL byte");
    }
    if (!names.insert(name).second) {
      Fail(path, "duplicate channel name '" + name + "'");
    }
  }
}

void ValidateBaseSize(int width, int height, const std::string& path) {
  if (width < 1 || height < 1 || width > kMaxSide || height > kMaxSide) {
    Fail(path, "bad base size " + std::to_string(width) + " x " +
                   std::to_string(height));
  }
}

// Checks sizes and names; `path` is used in messages.
void ValidateMipmap(const ParamMipmap& mipmap, const std::string& path) {
  ValidateChannels(mipmap.channels, path);
  if (mipmap.levels.empty()) Fail(path, "param mip map has no levels");
  const int width = mipmap.levels[0].width;
  const int height = mipmap.levels[0].height;
  ValidateBaseSize(width, height, path);
  // Either the full chain down to 1 x 1 or the base level alone.
  const int full_levels = MipLevelCount(width, height);
  const int expected_levels = mipmap.levels.size() == 1 ? 1 : full_levels;
  if (static_cast<int>(mipmap.levels.size()) != expected_levels) {
    Fail(path, "a " + std::to_string(width) + " x " + std::to_string(height) +
                   " base needs 1 level or " + std::to_string(full_levels) +
                   " levels (down to 1 x 1), got " +
                   std::to_string(mipmap.levels.size()));
  }
  for (int level = 0; level < expected_levels; ++level) {
    const ParamImage& image = mipmap.levels[level];
    const int level_width = MipLevelSize(width, level);
    const int level_height = MipLevelSize(height, level);
    const std::string label = "level " + std::to_string(level);
    if (image.width != level_width || image.height != level_height) {
      Fail(path, label + " is " + std::to_string(image.width) + " x " +
                     std::to_string(image.height) + ", expected " +
                     std::to_string(level_width) + " x " +
                     std::to_string(level_height));
    }
    if (image.data.size() != mipmap.channels.size()) {
      Fail(path, label + " has " + std::to_string(image.data.size()) +
                     " channels, expected " +
                     std::to_string(mipmap.channels.size()));
    }
    const size_t texels = static_cast<size_t>(level_width) * level_height;
    for (size_t c = 0; c < image.data.size(); ++c) {
      if (image.data[c].size() != texels) {
        Fail(path, label + " channel '" + mipmap.channels[c] + "' has " +
                       std::to_string(image.data[c].size()) +
                       " values, expected " + std::to_string(texels));
      }
    }
  }
}

// The frame buffer that holds rows [y0, y0 + rows) of `level` (and maybe
// more); it stays valid until the next call.
using BandSource = std::function<Imf::FrameBuffer(int level, int y0, int rows)>;

// What the EXR holds besides its values.
struct ExrLayout {
  std::vector<std::string> channels;
  int width = 0, height = 0;
  bool mipmapped = true;
  std::string index_text;
};

// Writes the EXR under `file` (a name OutputFile gave), with the index text
// in its header, `band_tiles` rows of tiles at a time (0: whole levels);
// returns "" or the problem. An InputError from `band` is passed on.
std::string WriteExr(const ExrLayout& layout, const std::string& file,
                     int band_tiles, const BandSource& band) {
  try {
    Imf::Header header(layout.width, layout.height);
    header.setTileDescription(Imf::TileDescription(
        kTileSize, kTileSize,
        layout.mipmapped ? Imf::MIPMAP_LEVELS : Imf::ONE_LEVEL,
        Imf::ROUND_DOWN));
    header.compression() = Imf::ZIP_COMPRESSION;
    for (const std::string& name : layout.channels) {
      header.channels().insert(name, Imf::Channel(Imf::FLOAT));
    }
    header.insert(kIndexAttribute, Imf::StringAttribute(layout.index_text));
    std::ofstream stream(file, std::ios::binary | std::ios::trunc);
    if (!stream) return std::string("cannot write: ") + std::strerror(errno);
    {
      Imf::StdOFStream exr_stream(stream, file.c_str());
      Imf::TiledOutputFile out(exr_stream, header);
      for (int level = 0; level < out.numLevels(); ++level) {
        const int tiles_y = out.numYTiles(level);
        const int step = band_tiles > 0 ? band_tiles : tiles_y;
        for (int ty = 0; ty < tiles_y; ty += step) {
          const int last = std::min(ty + step, tiles_y) - 1;
          const int y0 = ty * kTileSize;
          const int y1 =
              std::min(out.levelHeight(level), (last + 1) * kTileSize);
          out.setFrameBuffer(band(level, y0, y1 - y0));
          out.writeTiles(0, out.numXTiles(level) - 1, ty, last, level);
        }
      }
      // The destructor writes the tile offset table.
    }
    stream.close();
    if (!stream) return "cannot write: error while writing the OpenEXR file";
    return "";
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& error) {
    return std::string("cannot write OpenEXR file: ") + error.what();
  }
}

// The index text of a map, and `metadata_json` checked.
std::string IndexText(const ExrLayout& layout, int levels,
                      const std::string& metadata_json,
                      const std::string& path) {
  json metadata;
  try {
    metadata = json::parse(metadata_json.empty() ? "{}" : metadata_json);
  } catch (const json::exception& error) {
    Fail(path, std::string("metadata is not valid JSON: ") + error.what());
  }
  if (!metadata.is_object()) Fail(path, "metadata is not a JSON object");
  json index = {{"format", kFormat},
                {"exr", BaseName(path)},
                {"width", layout.width},
                {"height", layout.height},
                {"levels", levels},
                {"channels", layout.channels},
                {"metadata", std::move(metadata)}};
  try {
    return index.dump(2) + "\n";
  } catch (const json::exception& error) {
    // Channel names or metadata that are not valid UTF-8.
    Fail(path, std::string("cannot write index: ") + error.what());
  }
}

// Writes the EXR and its index copy and commits them together, after both
// were written: a failure leaves both as they were. A device or standard
// output gets the EXR alone.
void WriteFiles(const ExrLayout& layout, int band_tiles, const BandSource& band,
                const std::string& path) {
  OutputFile exr(path);
  const std::string problem =
      WriteExr(layout, exr.write_path(), band_tiles, band);
  if (!problem.empty()) Fail(path, problem);
  const OutputTarget target = ResolveOutput(path);
  if (target.direct()) {
    exr.Commit();
    return;
  }
  OutputFile copy(target.path + ".json");
  copy.Write(layout.index_text);
  exr.Commit();
  copy.Commit();
}

}  // namespace

void WriteParamMipmap(const ParamMipmap& mipmap, const std::string& path) {
  if (path.empty()) Fail(path, "cannot write: empty path");
  ValidateMipmap(mipmap, path);
  const std::string non_finite = FirstNonFinite(mipmap);
  if (!non_finite.empty()) Fail(path, "not written: " + non_finite);
  ExrLayout layout;
  layout.channels = mipmap.channels;
  layout.width = mipmap.levels[0].width;
  layout.height = mipmap.levels[0].height;
  const int levels = static_cast<int>(mipmap.levels.size());
  layout.mipmapped = levels == MipLevelCount(layout.width, layout.height);
  layout.index_text = IndexText(layout, levels, mipmap.metadata_json, path);
  WriteFiles(
      layout, 0,
      [&](int level, int, int) {
        return MakeFrameBuffer(mipmap.channels, mipmap.levels[level], 0, 0);
      },
      path);
}

void WriteParamMipmapBands(const ParamMipmapBands& bands,
                           const std::string& path) {
  if (path.empty()) Fail(path, "cannot write: empty path");
  ValidateChannels(bands.channels, path);
  ValidateBaseSize(bands.width, bands.height, path);
  ExrLayout layout;
  layout.channels = bands.channels;
  layout.width = bands.width;
  layout.height = bands.height;
  layout.mipmapped = bands.mipmapped;
  const int levels =
      bands.mipmapped ? MipLevelCount(bands.width, bands.height) : 1;
  layout.index_text = IndexText(layout, levels, bands.metadata_json, path);
  ParamImage band;
  WriteFiles(
      layout, kBandTiles,
      [&](int level, int y0, int rows) {
        band.width = MipLevelSize(bands.width, level);
        band.height = rows;
        band.data.resize(bands.channels.size());
        for (std::vector<float>& channel : band.data) {
          channel.resize(static_cast<size_t>(band.width) * rows);
        }
        bands.fill(level, y0, &band);
        const std::string non_finite =
            FirstNonFiniteIn(bands.channels, band, level, y0);
        if (!non_finite.empty()) Fail(path, "not written: " + non_finite);
        return MakeFrameBuffer(bands.channels, band, 0, y0);
      },
      path);
}

}  // namespace clothfit
