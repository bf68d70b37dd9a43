#include "io/hole_exr.h"

#include <cmath>
#include <nlohmann/json.hpp>
#include <utility>

#include "io/input_error.h"
#include "io/param_mipmap.h"
#include "models/holes.h"
#include "models/holes_distance.h"

namespace clothfit {
namespace {

using json = nlohmann::ordered_json;

const char* KindName(CountKind kind) {
  return kind == CountKind::kHoleCounts ? "clothfit-hole-counts 1"
                                        : "clothfit-hole-distances 1";
}

// The largest level-0 value of channel c.
int MaxBaseValue(CountKind kind, int c) {
  if (kind == CountKind::kHoleCounts && c >= kTriangleTopRight &&
      c <= kTriangleBottomRight) {
    return 2;
  }
  return 1;
}

[[noreturn]] void Fail(const std::string& path, const std::string& problem) {
  throw InputError(path + ": " + problem);
}

std::string TexelName(int level, int x, int y) {
  return "level " + std::to_string(level) + " texel (" + std::to_string(x) +
         ", " + std::to_string(y) + ")";
}

}  // namespace

std::vector<std::string> CountChannelNames(CountKind kind) {
  std::vector<std::string> names;
  if (kind == CountKind::kHoleCounts) {
    const char* const* n = HoleCountNames();
    names.assign(n, n + kHoleCountChannels);
    return names;
  }
  for (int d = 0; d < kDirections8; ++d) {
    for (int j = 0; j < kDistanceBins; ++j) {
      names.push_back(std::string("distance.") + Direction8Name(d) + "." +
                      std::to_string(j));
    }
  }
  return names;
}

void WriteCountPyramid(const CountPyramid& pyramid, CountKind kind,
                       const std::string& metadata_json,
                       const std::string& path) {
  const std::vector<std::string> names = CountChannelNames(kind);
  if (pyramid.channels() != static_cast<int>(names.size())) {
    Fail(path, "count pyramid has " + std::to_string(pyramid.channels()) +
                   " channels, expected " + std::to_string(names.size()));
  }
  json metadata = json::object();
  try {
    if (!metadata_json.empty()) metadata = json::parse(metadata_json);
  } catch (const json::exception& e) {
    Fail(path, std::string("metadata is not valid JSON: ") + e.what());
  }
  if (!metadata.is_object()) Fail(path, "metadata is not a JSON object");
  metadata["kind"] = KindName(kind);
  // One band of rows at a time: the floats of every level at once took
  // 5.7 GB for the run counts of a 4096 x 4096 mask (the pyramid: 0.5 GB).
  ParamMipmapBands bands;
  bands.channels = names;
  bands.width = pyramid.width(0);
  bands.height = pyramid.height(0);
  bands.metadata_json = metadata.dump();
  std::vector<float*> rows(names.size());
  bands.fill = [&](int level, int y0, ParamImage* band) {
    for (int y = 0; y < band->height; ++y) {
      const size_t offset = static_cast<size_t>(y) * band->width;
      for (size_t c = 0; c < names.size(); ++c) {
        rows[c] = band->data[c].data() + offset;
      }
      pyramid.RowCounts(level, y0 + y, rows.data());
    }
  };
  WriteParamMipmapBands(bands, path);
}

CountPyramid ReadCountPyramid(const std::string& path, CountKind kind,
                              std::string* metadata_json) {
  const ParamMipmap mipmap = ReadParamMipmap(path);
  json metadata;
  try {
    metadata = json::parse(mipmap.metadata_json);
  } catch (const json::exception& e) {
    Fail(path + ".json", std::string("metadata: ") + e.what());
  }
  const auto found = metadata.find("kind");
  if (found == metadata.end() || !found->is_string() ||
      found->get<std::string>() != KindName(kind)) {
    Fail(path + ".json", std::string("key 'metadata.kind': expected \"") +
                             KindName(kind) + "\"");
  }
  const std::vector<std::string> names = CountChannelNames(kind);
  if (mipmap.channels != names) {
    Fail(path + ".json", "key 'channels': expected the " +
                             std::to_string(names.size()) + " channels " +
                             names.front() + " ... " + names.back() +
                             " in order");
  }
  const ParamImage& base = mipmap.levels[0];
  const int channels = static_cast<int>(names.size());
  std::vector<uint8_t> values(static_cast<size_t>(base.width) * base.height *
                              channels);
  for (int y = 0; y < base.height; ++y) {
    for (int x = 0; x < base.width; ++x) {
      const size_t texel = static_cast<size_t>(y) * base.width + x;
      for (int c = 0; c < channels; ++c) {
        const float v = base.data[c][texel];
        const int max = MaxBaseValue(kind, c);
        if (!(v >= 0.0f && v <= static_cast<float>(max) &&
              v == std::floor(v))) {
          Fail(path, TexelName(0, x, y) + " channel '" + names[c] +
                         "': expected an integer count 0.." +
                         std::to_string(max) + ", got " + std::to_string(v));
        }
        values[texel * channels + c] = static_cast<uint8_t>(v);
      }
      if (kind == CountKind::kHoleCounts &&
          values[texel * channels + kOpaques]) {
        for (int c = 0; c < kOpaques; ++c) {
          if (values[texel * channels + c] != 0) {
            Fail(path,
                 TexelName(0, x, y) + " is opaque but has '" + names[c] +
                     "' = " + std::to_string(values[texel * channels + c]));
          }
        }
      }
    }
  }
  CountPyramid pyramid(base.width, base.height, channels, std::move(values));
  std::vector<double> sums(channels);
  for (size_t level = 1; level < mipmap.levels.size(); ++level) {
    const ParamImage& image = mipmap.levels[level];
    for (int y = 0; y < image.height; ++y) {
      for (int x = 0; x < image.width; ++x) {
        pyramid.Counts(static_cast<int>(level), x, y, sums.data());
        for (int c = 0; c < channels; ++c) {
          const float stored =
              image.data[c][static_cast<size_t>(y) * image.width + x];
          if (stored != static_cast<float>(sums[c])) {
            Fail(path, TexelName(static_cast<int>(level), x, y) + " channel '" +
                           names[c] + "' is " + std::to_string(stored) +
                           ", but the level-0 counts below it sum to " +
                           std::to_string(static_cast<int64_t>(sums[c])));
          }
        }
      }
    }
  }
  if (metadata_json) *metadata_json = metadata.dump();
  return pyramid;
}

}  // namespace clothfit
