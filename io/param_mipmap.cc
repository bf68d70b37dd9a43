#include "io/param_mipmap.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfStdIO.h>
#include <ImfStringAttribute.h>
#include <ImfTileDescription.h>
#include <ImfTileDescriptionAttribute.h>
#include <ImfTiledInputFile.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <new>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "io/atomic_file.h"
#include "io/input_error.h"
#include "io/json_text_internal.h"
#include "io/param_mipmap_internal.h"
#include "io/text_util.h"
#include "models/mip_levels.h"

namespace clothfit {
namespace param_mipmap_internal {

std::string FirstNonFiniteIn(const std::vector<std::string>& channels,
                             const ParamImage& image, int level, int y0) {
  for (size_t c = 0; c < image.data.size(); ++c) {
    const std::vector<float>& values = image.data[c];
    for (size_t i = 0; i < values.size(); ++i) {
      if (std::isfinite(values[i])) continue;
      const size_t w = static_cast<size_t>(std::max(image.width, 1));
      return "channel '" + (c < channels.size() ? channels[c] : "?") +
             "' at level " + std::to_string(level) + ", texel (" +
             std::to_string(i % w) + ", " + std::to_string(y0 + i / w) +
             ") is " + (std::isnan(values[i]) ? "NaN" : "infinite");
    }
  }
  return "";
}

std::string FirstNonFinite(const ParamMipmap& mipmap) {
  for (size_t level = 0; level < mipmap.levels.size(); ++level) {
    const std::string problem = FirstNonFiniteIn(
        mipmap.channels, mipmap.levels[level], static_cast<int>(level), 0);
    if (!problem.empty()) return problem;
  }
  return "";
}

Imf::FrameBuffer MakeFrameBuffer(const std::vector<std::string>& channels,
                                 const ParamImage& image, int x0, int y0) {
  Imf::FrameBuffer frame_buffer;
  const size_t x_stride = sizeof(float);
  const size_t y_stride = sizeof(float) * static_cast<size_t>(image.width);
  const ptrdiff_t origin =
      static_cast<ptrdiff_t>(x0) * static_cast<ptrdiff_t>(x_stride) +
      static_cast<ptrdiff_t>(y0) * static_cast<ptrdiff_t>(y_stride);
  for (size_t c = 0; c < channels.size(); ++c) {
    // OpenEXR addresses pixel (x, y) at base + x * xStride + y * yStride.
    char* base =
        reinterpret_cast<char*>(const_cast<float*>(image.data[c].data())) -
        origin;
    frame_buffer.insert(channels[c],
                        Imf::Slice(Imf::FLOAT, base, x_stride, y_stride));
  }
  return frame_buffer;
}

}  // namespace param_mipmap_internal

namespace {

using param_mipmap_internal::Fail;
using param_mipmap_internal::FirstNonFinite;
using param_mipmap_internal::kFormat;
using param_mipmap_internal::kIndexAttribute;
using param_mipmap_internal::kMaxSide;
using param_mipmap_internal::MakeFrameBuffer;

using nlohmann::json;

// The largest number of floats in all levels together (8 GiB); larger
// indexes are rejected as corrupt before anything is allocated.
constexpr int64_t kMaxFloats = int64_t{1} << 31;

// Reads a non-negative integer member of the index.
int IndexInt(const json& index, const char* key, const std::string& name) {
  const auto it = index.find(key);
  if (it == index.end()) Fail(name, std::string("missing key '") + key + "'");
  if (!it->is_number_integer() || it->get<int64_t>() < 0 ||
      it->get<int64_t>() > kMaxSide) {
    Fail(name, std::string("key '") + key + "': expected an integer in [0, " +
                   std::to_string(kMaxSide) + "], got " + it->dump());
  }
  return static_cast<int>(it->get<int64_t>());
}

struct Index {
  int width = 0, height = 0, levels = 0;
  std::vector<std::string> channels;
  std::string metadata_json = "{}";
};

// The index from its text (the EXR header's or the .exr.json copy's), named
// `name` in messages.
Index ParseIndex(const std::string& text, const std::string& name) {
  const json index = ParseJsonText<json>(text, name);
  if (!index.is_object()) Fail(name, "expected a JSON object");
  const auto format = index.find("format");
  if (format == index.end() || !format->is_string() ||
      format->get<std::string>() != kFormat) {
    Fail(name, std::string("key 'format': expected \"") + kFormat + "\"");
  }
  Index result;
  result.width = IndexInt(index, "width", name);
  result.height = IndexInt(index, "height", name);
  result.levels = IndexInt(index, "levels", name);
  if (result.width < 1 || result.height < 1) {
    Fail(name, "bad size " + std::to_string(result.width) + " x " +
                   std::to_string(result.height));
  }
  const int full_levels = MipLevelCount(result.width, result.height);
  if (result.levels != 1 && result.levels != full_levels) {
    Fail(name, "key 'levels': a " + std::to_string(result.width) + " x " +
                   std::to_string(result.height) + " base has 1 or " +
                   std::to_string(full_levels) + " levels, index says " +
                   std::to_string(result.levels));
  }
  const auto channels = index.find("channels");
  if (channels == index.end() || !channels->is_array() || channels->empty()) {
    Fail(name, "key 'channels': expected a non-empty array of names");
  }
  std::set<std::string> seen;
  for (const json& channel : *channels) {
    if (!channel.is_string() || channel.get<std::string>().empty()) {
      Fail(name,
           "key 'channels': expected non-empty names, got " + channel.dump());
    }
    if (!seen.insert(channel.get<std::string>()).second) {
      Fail(name, "key 'channels': duplicate name " + channel.dump());
    }
    result.channels.push_back(channel.get<std::string>());
  }
  const auto metadata = index.find("metadata");
  if (metadata != index.end()) {
    if (!metadata->is_object()) {
      Fail(name, "key 'metadata': expected a JSON object");
    }
    result.metadata_json = metadata->dump();
  }
  int64_t floats = 0;
  for (int level = 0; level < result.levels; ++level) {
    floats += static_cast<int64_t>(MipLevelSize(result.width, level)) *
              MipLevelSize(result.height, level);
  }
  if (floats * static_cast<int64_t>(result.channels.size()) > kMaxFloats) {
    Fail(name, "too large: " + std::to_string(result.channels.size()) +
                   " channels of " + std::to_string(result.width) + " x " +
                   std::to_string(result.height));
  }
  return result;
}

// The index: from the EXR header (clothfit 0.4 on), else from the .exr.json
// beside the EXR (files written before).
Index ReadIndex(const std::string& path, const Imf::Header& header) {
  const auto* attribute =
      header.findTypedAttribute<Imf::StringAttribute>(kIndexAttribute);
  if (attribute != nullptr) {
    return ParseIndex(attribute->value(),
                      path + ": header attribute '" + kIndexAttribute + "'");
  }
  const std::string copy = path + ".json";
  std::error_code error;
  if (!std::filesystem::exists(copy, error)) {
    Fail(copy, "missing: the JSON index of the parameter mip map " + path +
                   " (its header has none: written by clothfit 0.3 or earlier, "
                   "keep the two together)");
  }
  return ParseIndex(ReadFileToString(copy), copy);
}

void ReadExr(const std::string& path, ParamMipmap* mipmap) {
  Imf::TiledInputFile in(path.c_str());
  const Imf::Header& header = in.header();
  const Index index = ReadIndex(path, header);
  mipmap->channels = index.channels;
  mipmap->metadata_json = index.metadata_json;
  const bool one_level =
      header.hasTileDescription() && in.levelMode() == Imf::ONE_LEVEL;
  if (!header.hasTileDescription() ||
      !(one_level || (in.levelMode() == Imf::MIPMAP_LEVELS &&
                      in.levelRoundingMode() == Imf::ROUND_DOWN))) {
    Fail(path,
         "not a tiled OpenEXR file with one level or MIPMAP_LEVELS, "
         "ROUND_DOWN");
  }
  const Imath::Box2i& window = header.dataWindow();
  const int64_t width = int64_t{window.max.x} - window.min.x + 1;
  const int64_t height = int64_t{window.max.y} - window.min.y + 1;
  if (width != index.width || height != index.height) {
    Fail(path, "image is " + std::to_string(width) + " x " +
                   std::to_string(height) + ", index says " +
                   std::to_string(index.width) + " x " +
                   std::to_string(index.height));
  }
  if (in.numLevels() != index.levels) {
    Fail(path, "file has " + std::to_string(in.numLevels()) +
                   " levels, index says " + std::to_string(index.levels));
  }
  for (const std::string& name : index.channels) {
    if (header.channels().findChannel(name) == nullptr) {
      Fail(path, "channel '" + name + "' named in the index is missing");
    }
  }
  if (!in.isComplete()) Fail(path, "truncated or incomplete OpenEXR file");

  mipmap->levels.resize(index.levels);
  for (int level = 0; level < index.levels; ++level) {
    ParamImage& image = mipmap->levels[level];
    image.width = in.levelWidth(level);
    image.height = in.levelHeight(level);
    if (image.width != MipLevelSize(index.width, level) ||
        image.height != MipLevelSize(index.height, level)) {
      Fail(path, "level " + std::to_string(level) + " has an unexpected size");
    }
    image.data.assign(
        index.channels.size(),
        std::vector<float>(static_cast<size_t>(image.width) * image.height));
    const Imath::Box2i level_window = in.dataWindowForLevel(level);
    in.setFrameBuffer(MakeFrameBuffer(index.channels, image, level_window.min.x,
                                      level_window.min.y));
    in.readTiles(0, in.numXTiles(level) - 1, 0, in.numYTiles(level) - 1, level);
  }
}

}  // namespace

ParamMipmap ReadParamMipmap(const std::string& path) {
  const std::string problem = RegularFileProblem(path);
  if (!problem.empty()) Fail(path, "cannot read: " + problem);
  ParamMipmap mipmap;
  try {
    ReadExr(path, &mipmap);
    const std::string non_finite = FirstNonFinite(mipmap);
    if (!non_finite.empty()) {
      Fail(path, non_finite + " (a parameter mip map holds finite values)");
    }
  } catch (const InputError&) {
    throw;
  } catch (const std::bad_alloc&) {
    Fail(path, "out of memory reading the OpenEXR file");
  } catch (const std::exception& error) {
    // Iex::BaseExc derives from std::exception.
    Fail(path, std::string("cannot read OpenEXR file: ") + error.what());
  }
  return mipmap;
}

}  // namespace clothfit
