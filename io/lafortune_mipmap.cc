#include "io/lafortune_mipmap.h"

#include <algorithm>
#include <array>
#include <nlohmann/json.hpp>
#include <string>
#include <unordered_map>

#include "io/input_error.h"

namespace clothfit {
namespace {

const char* const kRgb[] = {"R", "G", "B"};

// "diffuse.R": channel c of an rgb entry.
std::string RgbChannel(const char* entry, int c) {
  return std::string(entry) + "." + kRgb[c];
}

// The lobe entries in the table's order (Cx, Cy, Cz, N).
std::vector<const ParamInfo*> LobeEntries() {
  std::vector<const ParamInfo*> entries;
  LafortuneLobe lobe;
  VisitParams(lobe, [&](const ParamInfo& info, glm::dvec3&) {
    entries.push_back(&info);
  });
  return entries;
}

// "lobe{k}.{entry}.{R,G,B}" for entry q = 3 entry + channel.
std::string LobeChannel(int k, int q) {
  return "lobe" + std::to_string(k) + "." +
         RgbChannel(LobeEntries()[q / 3]->name, q % 3);
}

}  // namespace

ParamMipmap ToParamMipmap(const std::vector<LafortuneTexelMap>& levels,
                          const std::vector<glm::dvec3>& views) {
  int lobes = 0;
  for (const LafortuneTexelMap& level : levels) {
    for (const LafortuneModel& t : level.texels) {
      lobes = std::max(lobes, static_cast<int>(t.params.lobes.size()));
    }
  }
  ParamMipmap m;
  m.channels = {"lobes", "relative_rms"};
  for (const char* c : {"X", "Y", "Z"}) {
    m.channels.push_back(std::string("normal.") + c);
  }
  for (int c = 0; c < 3; ++c) {
    m.channels.push_back(RgbChannel(kLafortuneDiffuse.name, c));
  }
  for (int k = 0; k < lobes; ++k) {
    for (int q = 0; q < 12; ++q) m.channels.push_back(LobeChannel(k, q));
  }
  for (size_t v = 0; v < views.size(); ++v) {
    for (const char* c : {"R", "G", "B", "A"}) {
      m.channels.push_back("lut." + std::to_string(v) + "." + c);
    }
  }
  for (const LafortuneTexelMap& level : levels) {
    ParamImage image;
    image.width = level.width;
    image.height = level.height;
    image.data.assign(m.channels.size(),
                      std::vector<float>(level.texels.size(), 0.0f));
    for (size_t i = 0; i < level.texels.size(); ++i) {
      const LafortuneModel& t = level.texels[i];
      const LafortuneParams& p = t.params;
      size_t ch = 0;
      image.data[ch++][i] = static_cast<float>(p.lobes.size());
      image.data[ch++][i] = static_cast<float>(
          i < level.relative_rms.size() ? level.relative_rms[i] : 0.0);
      for (int c = 0; c < 3; ++c) image.data[ch++][i] = t.normal[c];
      for (int c = 0; c < 3; ++c) image.data[ch++][i] = p.diffuse[c];
      for (int k = 0; k < lobes; ++k) {
        if (k >= static_cast<int>(p.lobes.size())) {
          ch += 12;  // zeros
          continue;
        }
        VisitParamsConst(p.lobes[k],
                         [&](const ParamInfo&, const glm::dvec3& field) {
                           for (int c = 0; c < 3; ++c) {
                             image.data[ch++][i] = static_cast<float>(field[c]);
                           }
                         });
      }
      const ViewTable& lut = t.lut;
      for (size_t v = 0; v < views.size(); ++v) {
        const bool has = v < lut.color.size();
        for (int c = 0; c < 3; ++c) {
          image.data[ch++][i] =
              has ? static_cast<float>(lut.color[v][c]) : 1.0f;
        }
        image.data[ch++][i] = has ? static_cast<float>(lut.alpha[v]) : 1.0f;
      }
    }
    m.levels.push_back(std::move(image));
  }
  nlohmann::ordered_json meta;
  meta["model"] = "lafortune";
  meta["lobes"] = lobes;
  meta["frame"] =
      "directions and normal.XYZ in the surface frame (normal +z, warp +x); "
      "the lobes in each texel's frame: n = normal.XYZ, b = normalize(n x "
      "x), t = b x n";
  meta["quantity"] = "cosine_weighted";
  meta["lut_interpolation"] = kLutInterpolation;
  nlohmann::ordered_json units;
  units[kLafortuneDiffuse.name] = kLafortuneDiffuse.unit;
  for (const ParamInfo* entry : LobeEntries()) units[entry->name] = entry->unit;
  units["normal"] = "unit vector (surface frame)";
  units["lut"] = "unitless factor (RGB) and coverage (A)";
  units["relative_rms"] = "RMS(model - data) / RMS(data)";
  meta["units"] = units;
  nlohmann::ordered_json json_views = nlohmann::ordered_json::array();
  for (const glm::dvec3& v : views) json_views.push_back({v.x, v.y, v.z});
  meta["views"] = json_views;
  m.metadata_json = meta.dump();
  return m;
}

namespace {

// Reads texels of a mip map written by ToParamMipmap: the metadata parsed
// and every channel looked up once, then each texel by index.
class MipmapTexelReader {
 public:
  explicit MipmapTexelReader(const ParamMipmap& mipmap) : mipmap_(mipmap) {
    for (size_t c = 0; c < mipmap.channels.size(); ++c) {
      index_.emplace(mipmap.channels[c], static_cast<int>(c));
    }
    const nlohmann::json meta = nlohmann::json::parse(mipmap.metadata_json);
    for (const auto& v : meta.at("views")) {
      views_.push_back(glm::dvec3(v[0].get<double>(), v[1].get<double>(),
                                  v[2].get<double>()));
    }
    for (int c = 0; c < 3; ++c) {
      diffuse_[c] = Find(RgbChannel(kLafortuneDiffuse.name, c));
      normal_[c] = Find(std::string("normal.") + "XYZ"[c]);
    }
    lobes_ = Find("lobes");
    // Lobe channels as far as they go (a texel's count is checked below).
    for (int k = 0;; ++k) {
      std::array<int, 12> lobe;
      for (int q = 0; q < 12; ++q) lobe[q] = Find(LobeChannel(k, q));
      if (lobe[0] < 0) break;
      lobe_channels_.push_back(lobe);
    }
    for (size_t v = 0; v < views_.size(); ++v) {
      const std::string prefix = "lut." + std::to_string(v) + ".";
      lut_.push_back({Find(prefix + "R"), Find(prefix + "G"),
                      Find(prefix + "B"), Find(prefix + "A")});
    }
  }

  LafortuneModel Texel(int level, size_t i) const {
    const ParamImage& image = mipmap_.levels[level];
    auto value = [&](int channel, const std::string& name) {
      if (channel < 0) {
        throw InputError("parameter mip map: no channel '" + name + "'");
      }
      return static_cast<double>(image.data[channel][i]);
    };
    LafortuneModel m;
    for (int c = 0; c < 3; ++c) {
      m.params.diffuse[c] =
          value(diffuse_[c], RgbChannel(kLafortuneDiffuse.name, c));
    }
    const glm::dvec3 normal(value(normal_[0], "normal.X"),
                            value(normal_[1], "normal.Y"),
                            value(normal_[2], "normal.Z"));
    if (glm::length(normal) > 0.0) m.normal = glm::normalize(normal);
    const int lobes = static_cast<int>(value(lobes_, "lobes"));
    for (int k = 0; k < lobes; ++k) {
      if (k >= static_cast<int>(lobe_channels_.size())) {
        value(-1, LobeChannel(k, 0));
      }
      const std::array<int, 12>& ch = lobe_channels_[k];
      LafortuneLobe lobe;
      int q = 0;
      VisitParams(lobe, [&](const ParamInfo&, glm::dvec3& field) {
        for (int c = 0; c < 3; ++c, ++q) {
          field[c] = value(ch[q], ch[q] < 0 ? LobeChannel(k, q) : "");
        }
      });
      m.params.lobes.push_back(lobe);
    }
    for (size_t v = 0; v < views_.size(); ++v) {
      const std::string name = "lut." + std::to_string(v);
      m.lut.views.push_back(views_[v]);
      m.lut.color.push_back(glm::dvec3(value(lut_[v][0], name + ".R"),
                                       value(lut_[v][1], name + ".G"),
                                       value(lut_[v][2], name + ".B")));
      m.lut.alpha.push_back(value(lut_[v][3], name + ".A"));
    }
    return m;
  }

 private:
  int Find(const std::string& name) const {
    const auto it = index_.find(name);
    return it == index_.end() ? -1 : it->second;
  }

  const ParamMipmap& mipmap_;
  std::unordered_map<std::string, int> index_;
  std::vector<glm::dvec3> views_;
  int diffuse_[3], normal_[3], lobes_;
  std::vector<std::array<int, 12>> lobe_channels_;
  std::vector<std::array<int, 4>> lut_;
};

void CheckLevel(const ParamMipmap& mipmap, int level) {
  if (level < 0 || level >= static_cast<int>(mipmap.levels.size())) {
    throw InputError("mip level " + std::to_string(level) + " out of range");
  }
}

}  // namespace

LafortuneModel TexelFromParamMipmap(const ParamMipmap& mipmap, int level, int x,
                                    int y) {
  CheckLevel(mipmap, level);
  const ParamImage& image = mipmap.levels[level];
  if (x < 0 || y < 0 || x >= image.width || y >= image.height) {
    throw InputError("texel out of range");
  }
  return MipmapTexelReader(mipmap).Texel(
      level, static_cast<size_t>(y) * image.width + x);
}

std::vector<LafortuneModel> LevelFromParamMipmap(const ParamMipmap& mipmap,
                                                 int level) {
  CheckLevel(mipmap, level);
  const MipmapTexelReader reader(mipmap);
  const ParamImage& image = mipmap.levels[level];
  std::vector<LafortuneModel> texels;
  texels.reserve(static_cast<size_t>(image.width) * image.height);
  for (size_t i = 0; i < static_cast<size_t>(image.width) * image.height; ++i) {
    texels.push_back(reader.Texel(level, i));
  }
  return texels;
}

}  // namespace clothfit
