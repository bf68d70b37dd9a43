#include "fitting/lafortune_mip.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <mutex>
#include <nlohmann/json.hpp>
#include <thread>
#include <unordered_map>

#include "io/input_error.h"

namespace clothfit {
namespace {

const char* const kRgb[] = {"R", "G", "B"};

}  // namespace

TexelFit FitTexelRows(const MeasurementTable& table, const ViewIndex& views,
                      const std::vector<size_t>& rows,
                      const LafortuneMipOptions& options) {
  const TexelSamples samples = CollectSamples(table, views, rows, nullptr);
  TexelFit best;
  std::vector<int> counts = {options.fit.lobes};
  if (options.tolerance > 0.0) counts = {0, 1, 2, 3};
  for (int k : counts) {
    LafortuneFitOptions o = options.fit;
    o.lobes = k;
    const LafortuneFitResult r = FitLafortune(samples, o);
    TexelFit fit;
    fit.model = r.model;
    fit.lobes = k;
    fit.samples = static_cast<int>(rows.size());
    fit.usable = r.usable;
    fit.message = r.message;
    fit.alternations = r.alternations;
    fit.iterations = r.iterations;
    fit.lut_change = r.lut_change;
    fit.final_cost = r.final_cost;
    fit.converged = r.converged;
    fit.termination = r.termination;
    // Errors over the rows, not the merged samples.
    LafortuneErrors(r.model, table, views, rows, &fit.rms, &fit.relative_rms,
                    &fit.view_relative_rms);
    const bool better =
        !best.usable || (fit.usable && fit.relative_rms < best.relative_rms);
    if (k == counts.front() || better) best = fit;
    if (options.tolerance > 0.0 && fit.usable &&
        fit.relative_rms <= options.tolerance) {
      best = fit;  // the smallest K that meets the tolerance
      break;
    }
  }
  return best;
}

LafortuneMipResult FitLafortuneMip(const MeasurementTable& table,
                                   const LafortuneMipOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  if (!table.has_texels) {
    throw InputError("a spatially varying fit needs s,t texel columns");
  }
  if (table.quantity == Quantity::kTransmittance) {
    throw InputError(
        "a Lafortune model predicts reflection, not "
        "transmittance");
  }
  LafortuneMipResult out;
  const ViewIndex views(table);
  out.views = views.views();
  int width = 0, height = 0;
  for (const TableRow& row : table.rows) {
    width = std::max(width, row.s + 1);
    height = std::max(height, row.t + 1);
  }
  // Rows of every texel of the level being fitted: level 0 from the table
  // (counted first, so that no list grows by doubling), level l+1 from 2 x 2
  // groups of level l (ROUND_DOWN: an odd last row/column joins the group
  // before it), made when level l is done. One level's lists at a time:
  // 8 bytes a row, not 8 per row and level.
  std::vector<std::vector<size_t>> texel_rows(static_cast<size_t>(width) *
                                              height);
  {
    std::vector<size_t> counts(texel_rows.size(), 0);
    for (const TableRow& row : table.rows) ++counts[row.t * width + row.s];
    for (size_t t = 0; t < counts.size(); ++t) texel_rows[t].reserve(counts[t]);
    for (size_t i = 0; i < table.rows.size(); ++i) {
      texel_rows[table.rows[i].t * width + table.rows[i].s].push_back(i);
    }
  }
  std::vector<std::pair<int, int>> sizes = {{width, height}};
  while (options.mip && (sizes.back().first > 1 || sizes.back().second > 1)) {
    sizes.push_back({std::max(1, sizes.back().first / 2),
                     std::max(1, sizes.back().second / 2)});
  }
  auto group_rows = [&](size_t l) {  // level l's lists -> level l + 1's
    const auto [w, h] = sizes[l];
    const auto [w2, h2] = sizes[l + 1];
    std::vector<std::vector<size_t>> next(static_cast<size_t>(w2) * h2);
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const int x2 = std::min(x / 2, w2 - 1), y2 = std::min(y / 2, h2 - 1);
        std::vector<size_t>& from = texel_rows[y * w + x];
        std::vector<size_t>& to = next[y2 * w2 + x2];
        to.insert(to.end(), from.begin(), from.end());
        std::vector<size_t>().swap(from);
      }
    }
    for (std::vector<size_t>& r : next) std::sort(r.begin(), r.end());
    texel_rows = std::move(next);
  };
  // Level by level (a group's fit starts from its children's, which must be
  // done); within a level every texel is one job. Results land in fixed
  // slots, so the thread count does not change them.
  size_t all_jobs = 0;
  for (const auto& [w, h] : sizes) {
    LafortuneLevel level;
    level.width = w;
    level.height = h;
    level.texels.resize(static_cast<size_t>(w) * h);
    level.samples = table.rows.size();  // every level holds every row
    all_jobs += level.texels.size();
    out.levels.push_back(std::move(level));
  }
  int threads = options.threads > 0
                    ? options.threads
                    : static_cast<int>(std::thread::hardware_concurrency());
  threads = std::clamp(threads, 1, 256);
  std::mutex progress_mutex;
  int done = 0;
  std::exception_ptr error;
  for (size_t l = 0; l < sizes.size() && !error; ++l) {
    const auto level_t0 = std::chrono::steady_clock::now();
    if (l > 0) group_rows(l - 1);
    // The children of each texel of level l (level l - 1's texels in its
    // group).
    std::vector<std::vector<const LafortuneModel*>> children(texel_rows.size());
    if (l > 0) {
      const LafortuneLevel& below = out.levels[l - 1];
      const int w2 = out.levels[l].width, h2 = out.levels[l].height;
      for (int y = 0; y < below.height; ++y) {
        for (int x = 0; x < below.width; ++x) {
          const int x2 = std::min(x / 2, w2 - 1), y2 = std::min(y / 2, h2 - 1);
          children[y2 * w2 + x2].push_back(
              &below.texels[y * below.width + x].model);
        }
      }
    }
    std::atomic<size_t> next_job{0};
    auto worker = [&]() {
      for (size_t t = next_job++; t < texel_rows.size(); t = next_job++) {
        try {
          LafortuneMipOptions texel_options = options;
          texel_options.fit.warm_starts = children[t];
          out.levels[l].texels[t] =
              FitTexelRows(table, views, texel_rows[t], texel_options);
        } catch (...) {
          std::lock_guard<std::mutex> lock(progress_mutex);
          if (!error) error = std::current_exception();
        }
        std::lock_guard<std::mutex> lock(progress_mutex);
        ++done;
        if (options.progress) {
          options.progress(done, static_cast<int>(all_jobs));
        }
      }
    };
    const int level_threads =
        std::min(threads, static_cast<int>(texel_rows.size()));
    std::vector<std::thread> pool;
    for (int i = 1; i < level_threads; ++i) pool.emplace_back(worker);
    worker();
    for (std::thread& t : pool) t.join();
    out.levels[l].seconds = std::chrono::duration<double>(
                                std::chrono::steady_clock::now() - level_t0)
                                .count();
  }
  if (error) std::rethrow_exception(error);
  out.fits = static_cast<int>(all_jobs);
  out.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0)
          .count();
  return out;
}

ParamMipmap ToParamMipmap(const LafortuneMipResult& result) {
  int lobes = 0;
  for (const LafortuneLevel& level : result.levels) {
    for (const TexelFit& t : level.texels) {
      lobes = std::max(lobes, static_cast<int>(t.model.params.lobes.size()));
    }
  }
  ParamMipmap m;
  m.channels = {"lobes", "relative_rms"};
  for (const char* c : {"X", "Y", "Z"}) {
    m.channels.push_back(std::string("normal.") + c);
  }
  for (const char* c : kRgb) m.channels.push_back(std::string("diffuse.") + c);
  for (int k = 0; k < lobes; ++k) {
    for (const char* p : {"Cx", "Cy", "Cz", "N"}) {
      for (const char* c : kRgb) {
        m.channels.push_back("lobe" + std::to_string(k) + "." + p + "." + c);
      }
    }
  }
  for (size_t v = 0; v < result.views.size(); ++v) {
    for (const char* c : {"R", "G", "B", "A"}) {
      m.channels.push_back("lut." + std::to_string(v) + "." + c);
    }
  }
  for (const LafortuneLevel& level : result.levels) {
    ParamImage image;
    image.width = level.width;
    image.height = level.height;
    image.data.assign(m.channels.size(),
                      std::vector<float>(level.texels.size(), 0.0f));
    for (size_t i = 0; i < level.texels.size(); ++i) {
      const TexelFit& t = level.texels[i];
      const LafortuneParams& p = t.model.params;
      size_t ch = 0;
      image.data[ch++][i] = static_cast<float>(p.lobes.size());
      image.data[ch++][i] = static_cast<float>(t.relative_rms);
      for (int c = 0; c < 3; ++c) image.data[ch++][i] = t.model.normal[c];
      for (int c = 0; c < 3; ++c) image.data[ch++][i] = p.diffuse[c];
      for (int k = 0; k < lobes; ++k) {
        const bool has = k < static_cast<int>(p.lobes.size());
        for (int q = 0; q < 4; ++q) {
          for (int c = 0; c < 3; ++c) {
            double value = 0.0;
            if (has) {
              const LafortuneLobe& lobe = p.lobes[k];
              const glm::dvec3* fields[] = {&lobe.cx, &lobe.cy, &lobe.cz,
                                            &lobe.n};
              value = (*fields[q])[c];
            }
            image.data[ch++][i] = static_cast<float>(value);
          }
        }
      }
      const ViewTable& lut = t.model.lut;
      for (size_t v = 0; v < result.views.size(); ++v) {
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
  meta["lut_interpolation"] = "shepard, angular distance power 3";
  meta["units"] = {{"diffuse", "unitless reflectance"},
                   {"Cx/Cy/Cz", "unitless"},
                   {"N", "unitless exponent"},
                   {"normal", "unit vector (surface frame)"},
                   {"lut", "unitless factor (RGB) and coverage (A)"},
                   {"relative_rms", "RMS(model - data) / RMS(data)"}};
  nlohmann::ordered_json views = nlohmann::ordered_json::array();
  for (const glm::dvec3& v : result.views) views.push_back({v.x, v.y, v.z});
  meta["views"] = views;
  m.metadata_json = meta.dump();
  return m;
}

namespace {

const char* const kLobeFields[] = {"Cx", "Cy", "Cz", "N"};

// "lobe{k}.{field}.{R,G,B}" for entry q = 3 field + channel.
std::string LobeChannel(int k, int q) {
  return "lobe" + std::to_string(k) + "." + kLobeFields[q / 3] + "." +
         kRgb[q % 3];
}

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
      diffuse_[c] = Find(std::string("diffuse.") + kRgb[c]);
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
          value(diffuse_[c], std::string("diffuse.") + kRgb[c]);
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
      glm::dvec3* fields[] = {&lobe.cx, &lobe.cy, &lobe.cz, &lobe.n};
      for (int q = 0; q < 12; ++q) {
        (*fields[q / 3])[q % 3] =
            value(ch[q], ch[q] < 0 ? LobeChannel(k, q) : "");
      }
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
