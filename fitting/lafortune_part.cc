#include "fitting/lafortune_part.h"

#include <algorithm>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "io/input_error.h"
#include "io/params_json.h"
#include "models/mip_levels.h"

namespace clothfit {
namespace {

using Json = nlohmann::ordered_json;

// What a texel's report says, in the part's "texels" of a level.
enum Flag : int {
  kUsable = 1,
  kConverged = 2,
  kSolveFallback = 4,
};

bool PowerOfTwo(int n) { return n > 0 && (n & (n - 1)) == 0; }

std::string Block(int x, int y, int width, int height) {
  return std::to_string(x) + "," + std::to_string(y) + "," +
         std::to_string(width) + "," + std::to_string(height);
}

// The reports of a level's texels as columns; the texts only where the
// summary names a texel (unusable, at a search limit, not converged,
// scaled to conserve energy).
Json ReportsJson(const LafortuneLevel& level) {
  Json relative = Json::array(), view = Json::array(), albedo = Json::array(),
       scale = Json::array(), alternations = Json::array(),
       iterations = Json::array(), limit = Json::array(), flags = Json::array(),
       notes = Json::object();
  for (size_t i = 0; i < level.texels.size(); ++i) {
    const FitReport& r = level.texels[i].report;
    relative.push_back(r.relative_rms);
    view.push_back(r.view_relative_rms);
    albedo.push_back(r.max_albedo);
    scale.push_back(r.energy_scale);
    alternations.push_back(r.alternations);
    iterations.push_back(r.iterations);
    limit.push_back(r.at_search_limit);
    flags.push_back((r.usable ? kUsable : 0) | (r.converged ? kConverged : 0) |
                    (r.solve_fallback ? kSolveFallback : 0));
    if (!r.usable || r.at_search_limit > 0 || !r.converged ||
        r.energy_scale < 1.0) {
      notes[std::to_string(i)] = {r.message, r.termination, r.max_albedo_at};
    }
  }
  Json out;
  out["relative_rms"] = relative;
  out["view_relative_rms"] = view;
  out["max_albedo"] = albedo;
  out["energy_scale"] = scale;
  out["alternations"] = alternations;
  out["iterations"] = iterations;
  out["at_search_limit"] = limit;
  out["flags"] = flags;
  out["notes"] = notes;
  return out;
}

void ReadReports(const Json& j, LafortuneLevel* level) {
  for (size_t i = 0; i < level->texels.size(); ++i) {
    FitReport& r = level->texels[i].report;
    r.relative_rms = j.at("relative_rms").at(i).get<double>();
    r.view_relative_rms = j.at("view_relative_rms").at(i).get<double>();
    r.max_albedo = j.at("max_albedo").at(i).get<double>();
    r.energy_scale = j.at("energy_scale").at(i).get<double>();
    r.alternations = j.at("alternations").at(i).get<int>();
    r.iterations = j.at("iterations").at(i).get<int>();
    r.at_search_limit = j.at("at_search_limit").at(i).get<int>();
    const int flags = j.at("flags").at(i).get<int>();
    r.usable = (flags & kUsable) != 0;
    r.converged = (flags & kConverged) != 0;
    r.solve_fallback = (flags & kSolveFallback) != 0;
    const auto note = j.at("notes").find(std::to_string(i));
    if (note != j.at("notes").end()) {
      r.message = note->at(0).get<std::string>();
      r.termination = note->at(1).get<std::string>();
      r.max_albedo_at = note->at(2).get<std::string>();
    }
  }
}

}  // namespace

std::string LafortuneRegionProblem(int x, int y, int width, int height,
                                   int texture_width, int texture_height) {
  const std::string texture = std::to_string(texture_width) + " x " +
                              std::to_string(texture_height) + " texels";
  if (!PowerOfTwo(width) || !PowerOfTwo(height)) {
    return "width and height must be powers of two, got " +
           Block(x, y, width, height);
  }
  if (texture_width % width != 0 || texture_height % height != 0) {
    return "a block of " + std::to_string(width) + " x " +
           std::to_string(height) + " does not divide the texture of " +
           texture + " (take a smaller block)";
  }
  if (x < 0 || y < 0 || x % width != 0 || y % height != 0) {
    return "x0 and y0 must be multiples of the width and height, got " +
           Block(x, y, width, height);
  }
  if (x + width > texture_width || y + height > texture_height) {
    return "block " + Block(x, y, width, height) +
           " is not inside the texture of " + texture;
  }
  return "";
}

size_t LafortunePartLevels(const LafortunePartInfo& info) {
  if (!info.mip) return 1;
  size_t levels = 1;
  for (int side = std::min(info.width, info.height); side > 1; side >>= 1) {
    ++levels;
  }
  return levels;
}

ParamMipmap ToPartMipmap(const LafortuneMipResult& block,
                         const LafortunePartInfo& info) {
  ParamMipmap map = ToParamMipmap(block);
  Json meta = Json::parse(map.metadata_json);
  Json part;
  part["format"] = 1;
  part["block"] = {info.x, info.y, info.width, info.height};
  part["texture"] = {info.texture_width, info.texture_height};
  part["mip"] = info.mip;
  part["stack"] = info.stack;
  part["fit"] = info.fit;
  const size_t levels = LafortunePartLevels(info);
  Json reports = Json::array();
  for (size_t l = 0; l < levels; ++l) {
    reports.push_back(ReportsJson(block.levels[l]));
  }
  part["reports"] = reports;
  // The last level's models to the last bit (17 digits): the fits above
  // the blocks start from them.
  Json models = Json::array();
  for (const LafortuneFitResult& t : block.levels[levels - 1].texels) {
    models.push_back(Json::parse(FormatParamFile(ParamFile(t.params))));
  }
  part["models"] = models;
  meta["part"] = part;
  map.metadata_json = meta.dump();
  return map;
}

LafortunePart ReadLafortunePart(const std::string& path) {
  LafortunePart part;
  part.path = path;
  part.map = ReadParamMipmap(path);
  const Json meta = Json::parse(part.map.metadata_json);
  if (!meta.contains("part")) {
    throw InputError(path +
                     ": not a part of a texture fitted in blocks (its index "
                     "has no metadata.part; clothfit fit --region writes "
                     "parts)");
  }
  try {
    const Json& j = meta.at("part");
    if (j.at("format").get<int>() != 1) {
      throw InputError(path + ": key 'part.format': this clothfit reads 1");
    }
    LafortunePartInfo& info = part.info;
    const std::vector<int> block = j.at("block").get<std::vector<int>>();
    const std::vector<int> texture = j.at("texture").get<std::vector<int>>();
    if (block.size() != 4 || texture.size() != 2) {
      throw InputError(path + ": key 'part.block' or 'part.texture': size");
    }
    info.x = block[0];
    info.y = block[1];
    info.width = block[2];
    info.height = block[3];
    info.texture_width = texture[0];
    info.texture_height = texture[1];
    info.mip = j.at("mip").get<bool>();
    info.stack = j.at("stack").get<std::string>();
    info.fit = j.at("fit").get<std::vector<std::string>>();
    const std::string problem =
        LafortuneRegionProblem(info.x, info.y, info.width, info.height,
                               info.texture_width, info.texture_height);
    if (!problem.empty()) {
      throw InputError(path + ": key 'part.block': " + problem);
    }
    const size_t levels = LafortunePartLevels(info);
    if (part.map.levels.size() < levels ||
        part.map.levels[0].width != info.width ||
        part.map.levels[0].height != info.height) {
      throw InputError(path + ": the map's levels are not those of block " +
                       Block(info.x, info.y, info.width, info.height));
    }
    const auto lobes_channel =
        std::find(part.map.channels.begin(), part.map.channels.end(), "lobes");
    if (lobes_channel == part.map.channels.end()) {
      throw InputError(path + ": no channel 'lobes'");
    }
    for (size_t l = 0; l < levels; ++l) {
      LafortuneLevel level;
      level.width = part.map.levels[l].width;
      level.height = part.map.levels[l].height;
      level.texels.resize(static_cast<size_t>(level.width) * level.height);
      const std::vector<float>& count =
          part.map.levels[l].data[lobes_channel - part.map.channels.begin()];
      for (size_t i = 0; i < level.texels.size(); ++i) {
        if (!(count[i] >= 0.0f && count[i] <= 3.0f)) {
          throw InputError(path + ": channel 'lobes' of level " +
                           std::to_string(l) + ": not a lobe count (0 to 3)");
        }
        level.texels[i].params.params.lobes.resize(
            static_cast<size_t>(count[i]));
      }
      ReadReports(j.at("reports").at(l), &level);
      part.result.levels.push_back(std::move(level));
    }
    LafortuneLevel& last = part.result.levels.back();
    const Json& models = j.at("models");
    if (models.size() != last.texels.size()) {
      throw InputError(
          path + ": key 'part.models': " + std::to_string(models.size()) +
          " models for " + std::to_string(last.texels.size()) + " texels");
    }
    for (size_t i = 0; i < models.size(); ++i) {
      last.texels[i].params = ModelOf<LafortuneModel>(
          ParseParamFile(models[i].dump(),
                         path + ": part.models[" + std::to_string(i) + "]"),
          path);
    }
  } catch (const Json::exception& e) {
    throw InputError(path + ": metadata.part: " + e.what());
  }
  return part;
}

LafortuneMipResult AssembleLafortuneParts(
    const std::vector<LafortunePart>& parts) {
  if (parts.empty()) throw InputError("no parts to merge");
  const LafortunePart& first = parts.front();
  const LafortunePartInfo& ref = first.info;
  auto differs = [&](const LafortunePart& p, const std::string& what) {
    throw InputError(p.path + ": " + what + " differs from " + first.path +
                     "'s (parts of one fit must share it)");
  };
  const int columns = ref.texture_width / ref.width;
  const int rows = ref.texture_height / ref.height;
  std::vector<int> owner(static_cast<size_t>(columns) * rows, -1);
  for (size_t k = 0; k < parts.size(); ++k) {
    const LafortunePartInfo& info = parts[k].info;
    if (info.texture_width != ref.texture_width ||
        info.texture_height != ref.texture_height) {
      differs(parts[k], "the texture's size");
    }
    if (info.width != ref.width || info.height != ref.height) {
      differs(parts[k], "the block size");
    }
    if (info.stack != ref.stack) differs(parts[k], "the stack");
    if (info.fit != ref.fit || info.mip != ref.mip) {
      differs(parts[k], "the fit's options");
    }
    int& cell = owner[static_cast<size_t>(info.y / info.height) * columns +
                      info.x / info.width];
    if (cell >= 0) {
      throw InputError("block " +
                       Block(info.x, info.y, info.width, info.height) +
                       " is in two parts: " + parts[cell].path + " and " +
                       parts[k].path + " (each block once)");
    }
    cell = static_cast<int>(k);
  }
  for (size_t c = 0; c < owner.size(); ++c) {
    if (owner[c] >= 0) continue;
    const size_t missing = std::count(owner.begin(), owner.end(), -1);
    throw InputError("block " +
                     Block(static_cast<int>(c % columns) * ref.width,
                           static_cast<int>(c / columns) * ref.height,
                           ref.width, ref.height) +
                     " is missing: no part covers it (" +
                     std::to_string(missing) + " of " +
                     std::to_string(owner.size()) + " blocks missing)");
  }
  LafortuneMipResult out;
  const size_t levels = LafortunePartLevels(ref);
  for (size_t l = 0; l < levels; ++l) {
    LafortuneLevel level;
    level.width = MipLevelSize(ref.texture_width, static_cast<int>(l));
    level.height = MipLevelSize(ref.texture_height, static_cast<int>(l));
    level.texels.resize(static_cast<size_t>(level.width) * level.height);
    for (const LafortunePart& part : parts) {
      const LafortuneLevel& block = part.result.levels[l];
      const int x0 = part.info.x >> l, y0 = part.info.y >> l;
      for (int y = 0; y < block.height; ++y) {
        for (int x = 0; x < block.width; ++x) {
          level.texels[static_cast<size_t>(y0 + y) * level.width + x0 + x] =
              block.texels[static_cast<size_t>(y) * block.width + x];
        }
      }
    }
    out.levels.push_back(std::move(level));
  }
  return out;
}

ParamMipmap MergedParamMipmap(const LafortuneMipResult& merged,
                              const std::vector<LafortunePart>& parts) {
  ParamMipmap map = ToParamMipmap(merged);
  for (const LafortunePart& part : parts) {
    std::map<std::string, size_t> index;
    for (size_t c = 0; c < part.map.channels.size(); ++c) {
      index[part.map.channels[c]] = c;
    }
    for (size_t l = 0; l < LafortunePartLevels(part.info); ++l) {
      const ParamImage& from = part.map.levels[l];
      ParamImage& to = map.levels[l];
      const int x0 = part.info.x >> l, y0 = part.info.y >> l;
      for (size_t c = 0; c < map.channels.size(); ++c) {
        const auto it = index.find(map.channels[c]);
        for (int y = 0; y < from.height; ++y) {
          for (int x = 0; x < from.width; ++x) {
            const size_t i = static_cast<size_t>(y) * from.width + x;
            // A channel the block lacks: a lobe none of its texels has,
            // zero as ToParamMipmap writes it.
            to.data[c][static_cast<size_t>(y0 + y) * to.width + x0 + x] =
                it == index.end() ? 0.0f : from.data[it->second][i];
          }
        }
      }
    }
  }
  return map;
}

}  // namespace clothfit
