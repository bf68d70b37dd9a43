#include "fitting/lafortune_mip.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <mutex>
#include <nlohmann/json.hpp>
#include <thread>
#include <unordered_map>

#include "fitting/lafortune_covariance.h"
#include "io/input_error.h"
#include "models/mip_levels.h"

namespace clothfit {

namespace {

NoiseModel LafortuneNoise(const MeasurementTable& table,
                          const NoiseModel& noise) {
  NoiseModel n = noise;
  if (n.kind == NoiseKind::kDefault && !table.has_sigma) {
    n.kind = NoiseKind::kAbsolute;
  }
  return n;
}

}  // namespace

Weighting LafortuneWeighting(const MeasurementTable& table,
                             const NoiseModel& noise) {
  return Weighting(table, LafortuneNoise(table, noise));
}

Weighting LafortuneWeighting(
    const MeasurementTable& table, const NoiseModel& noise,
    const std::function<std::vector<double>(int channel)>& channel_values) {
  return Weighting(table, LafortuneNoise(table, noise), channel_values);
}

std::vector<int> LafortuneCandidateLobes(const LafortuneMipOptions& options) {
  if (options.tolerance > 0.0) return {0, 1, 2, 3};
  return {options.fit.lobes};
}

LafortuneFitResult FitLafortuneCandidate(const TexelSamples& samples, int lobes,
                                         int skipped,
                                         const LafortuneMipOptions& options) {
  LafortuneFitOptions o = options.fit;
  o.lobes = lobes;
  LafortuneFitResult fit = FitLafortune(samples, o);
  fit.report.rows_not_used = skipped;
  return fit;
}

bool LafortuneCandidates::Offer(LafortuneFitResult fit) {
  const bool better = !best_.report.usable ||
                      (fit.report.usable &&
                       fit.report.relative_rms < best_.report.relative_rms);
  const bool first = !offered_;
  offered_ = true;
  if (tolerance_ > 0.0 && fit.report.usable &&
      fit.report.relative_rms <= tolerance_) {
    best_ = std::move(fit);  // the smallest K that meets the tolerance
    return true;
  }
  if (first || better) best_ = std::move(fit);
  return false;
}

namespace {

// FitTexelRows on the rows' samples (CollectSamples; `skipped` rows left
// out), which the caller keeps.
LafortuneFitResult FitTexelSamples(const TexelSamples& samples, int skipped,
                                   const MeasurementTable& table,
                                   const ViewIndex& views,
                                   const std::vector<size_t>& rows,
                                   const LafortuneMipOptions& options) {
  LafortuneCandidates candidates(options.tolerance);
  for (int k : LafortuneCandidateLobes(options)) {
    LafortuneFitResult fit =
        FitLafortuneCandidate(samples, k, skipped, options);
    // Errors over the rows, not the merged samples.
    LafortuneErrors(fit.params, table, views, rows, &fit.report.rms,
                    &fit.report.relative_rms, &fit.report.view_relative_rms);
    if (candidates.Offer(std::move(fit))) break;
  }
  return candidates.Take();
}

}  // namespace

LafortuneFitResult FitTexelRows(const MeasurementTable& table,
                                const Weighting& weighting,
                                const ViewIndex& views,
                                const std::vector<size_t>& rows,
                                const LafortuneMipOptions& options) {
  int skipped = 0;
  const TexelSamples samples =
      CollectSamples(table, weighting, views, rows, &skipped);
  return FitTexelSamples(samples, skipped, table, views, rows, options);
}

std::vector<std::vector<const LafortuneModel*>> LafortuneChildren(
    const LafortuneLevel& below, int width, int height) {
  std::vector<std::vector<const LafortuneModel*>> children(
      static_cast<size_t>(width) * height);
  for (int y = 0; y < below.height; ++y) {
    for (int x = 0; x < below.width; ++x) {
      children[static_cast<size_t>(MipParent(y, height)) * width +
               MipParent(x, width)]
          .push_back(
              &below.texels[static_cast<size_t>(y) * below.width + x].params);
    }
  }
  return children;
}

void RunTexelJobs(size_t jobs, int threads,
                  const std::function<void(size_t)>& job,
                  const std::function<void()>& done) {
  if (threads <= 0) {
    threads = static_cast<int>(std::thread::hardware_concurrency());
  }
  threads = std::clamp(threads, 1, 256);
  std::mutex mutex;
  std::exception_ptr error;
  std::atomic<size_t> next_job{0};
  auto worker = [&]() {
    for (size_t t = next_job++; t < jobs; t = next_job++) {
      try {
        job(t);
      } catch (...) {
        std::lock_guard<std::mutex> lock(mutex);
        if (!error) error = std::current_exception();
      }
      std::lock_guard<std::mutex> lock(mutex);
      if (done) done();
    }
  };
  const int pool_threads =
      static_cast<int>(std::min<size_t>(threads, std::max<size_t>(jobs, 1)));
  std::vector<std::thread> pool;
  for (int i = 1; i < pool_threads; ++i) pool.emplace_back(worker);
  worker();
  for (std::thread& t : pool) t.join();
  if (error) std::rethrow_exception(error);
}

LafortuneMipSummary SummarizeLafortuneMip(const LafortuneMipResult& result) {
  LafortuneMipSummary out;
  for (size_t l = 0; l < result.levels.size(); ++l) {
    const LafortuneLevel& level = result.levels[l];
    LafortuneLevelSummary s;
    s.width = level.width;
    s.height = level.height;
    s.samples = level.samples;
    for (size_t i = 0; i < level.texels.size(); ++i) {
      const LafortuneFitResult& t = level.texels[i];
      const std::string where = "level " + std::to_string(l) + ", texel (" +
                                std::to_string(i % level.width) + ", " +
                                std::to_string(i / level.width) + "): ";
      if (!t.report.usable && out.unusable++ == 0) {
        out.first_unusable = where + t.report.message;
      }
      // Scaled to conserve energy: counted as such, not also as a cap.
      const bool scaled = t.report.usable && t.report.energy_scale < 1.0;
      if (scaled) {
        ++s.energy_scaled;
        if (out.energy_scaled++ == 0) {
          out.first_energy_scaled = where + t.report.max_albedo_at;
        }
      }
      s.max_albedo = std::max(s.max_albedo, t.report.max_albedo);
      s.solve_fallback += t.report.solve_fallback ? 1 : 0;
      if (t.report.usable && t.report.at_search_limit > 0) {
        ++s.at_search_limit;
        if (out.at_search_limit++ == 0) {
          out.first_at_search_limit = where + t.report.message;
        }
      } else if (t.report.usable && !t.report.converged && !scaled &&
                 out.not_converged++ == 0) {
        out.first_not_converged = where + t.report.termination;
      }
      out.worst_relative_rms =
          std::max(out.worst_relative_rms, t.report.relative_rms);
      s.mean_relative_rms += t.report.relative_rms;
      s.mean_view_relative_rms += t.report.view_relative_rms;
      s.mean_alternations += t.report.alternations;
      s.mean_iterations += t.report.iterations;
      ++s.lobe_counts[std::clamp(static_cast<int>(t.params.params.lobes.size()),
                                 0, 3)];
    }
    const double n = std::max<size_t>(1, level.texels.size());
    s.mean_relative_rms /= n;
    s.mean_view_relative_rms /= n;
    s.mean_alternations /= n;
    s.mean_iterations /= n;
    out.levels.push_back(s);
  }
  return out;
}

LafortuneMipResult FitLafortuneMip(const MeasurementTable& table,
                                   const LafortuneMipOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  RequireWeightedRows(table);
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
  const Weighting weighting = LafortuneWeighting(table, options.noise);
  out.views = views.views();
  // The map is (largest s + 1) x (largest t + 1) texels. A texel index far
  // beyond the others (a typo, a column of another table) would make a
  // map of mostly empty texels, each a failed fit, or one too large to
  // allocate: a map with more texels than the table has rows is bad input.
  if (table.rows.empty()) throw InputError("the table has no rows");
  auto texels = [](const TableRow& r) {
    return (static_cast<int64_t>(r.s) + 1) * (static_cast<int64_t>(r.t) + 1);
  };
  int64_t wide = 0, high = 0;
  const TableRow* largest = &table.rows.front();
  for (const TableRow& row : table.rows) {
    if (texels(row) > texels(*largest)) largest = &row;
    wide = std::max<int64_t>(wide, static_cast<int64_t>(row.s) + 1);
    high = std::max<int64_t>(high, static_cast<int64_t>(row.t) + 1);
  }
  if (wide * high > static_cast<int64_t>(table.rows.size())) {
    throw InputError(
        FormatLocation(table.source.empty() ? "table" : table.source,
                       largest->source_line, 0) +
        ": texel (" + std::to_string(largest->s) + ", " +
        std::to_string(largest->t) + ") makes the texture " +
        std::to_string(wide) + " x " + std::to_string(high) +
        " texels, more than the table's " + std::to_string(table.rows.size()) +
        " rows: most texels would have no data (s and t count texels from "
        "0)");
  }
  const int width = static_cast<int>(wide), height = static_cast<int>(high);
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
  std::vector<std::pair<int, int>> sizes;
  const int levels = options.mip ? MipLevelCount(width, height) : 1;
  for (int l = 0; l < levels; ++l) {
    sizes.push_back({MipLevelSize(width, l), MipLevelSize(height, l)});
  }
  auto group_rows = [&](size_t l) {  // level l's lists -> level l + 1's
    const auto [w, h] = sizes[l];
    const auto [w2, h2] = sizes[l + 1];
    std::vector<std::vector<size_t>> next(static_cast<size_t>(w2) * h2);
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const int x2 = MipParent(x, w2), y2 = MipParent(y, h2);
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
  int done = 0;
  for (size_t l = 0; l < sizes.size(); ++l) {
    const auto level_t0 = std::chrono::steady_clock::now();
    if (l > 0) group_rows(l - 1);
    // The children of each texel of level l (level l - 1's texels in its
    // group).
    const std::vector<std::vector<const LafortuneModel*>> children =
        l > 0 ? LafortuneChildren(out.levels[l - 1], out.levels[l].width,
                                  out.levels[l].height)
              : std::vector<std::vector<const LafortuneModel*>>(
                    texel_rows.size());
    RunTexelJobs(
        texel_rows.size(), options.threads,
        [&](size_t t) {
          LafortuneMipOptions texel_options = options;
          texel_options.fit.warm_starts = children[t];
          out.levels[l].texels[t] = FitTexelRows(table, weighting, views,
                                                 texel_rows[t], texel_options);
        },
        [&] {
          ++done;
          if (options.progress) {
            options.progress(done, static_cast<int>(all_jobs));
          }
        });
    out.levels[l].seconds = std::chrono::duration<double>(
                                std::chrono::steady_clock::now() - level_t0)
                                .count();
  }
  out.fits = static_cast<int>(all_jobs);
  out.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0)
          .count();
  return out;
}

int LafortuneMipGroup(const LafortuneMipResult& r, size_t level, int s, int t) {
  if (level >= r.levels.size() || s < 0 || t < 0 || s >= r.levels[0].width ||
      t >= r.levels[0].height) {
    return -1;
  }
  for (size_t k = 1; k <= level; ++k) {
    s = MipParent(s, r.levels[k].width);
    t = MipParent(t, r.levels[k].height);
  }
  return t * r.levels[level].width + s;
}

ParamMipmap ToParamMipmap(const LafortuneMipResult& result,
                          const std::string& selection_json) {
  std::vector<LafortuneTexelMap> levels;
  for (const LafortuneLevel& level : result.levels) {
    LafortuneTexelMap map;
    map.width = level.width;
    map.height = level.height;
    for (const LafortuneFitResult& t : level.texels) {
      map.texels.push_back(t.params);
      map.relative_rms.push_back(t.report.relative_rms);
    }
    levels.push_back(std::move(map));
  }
  ParamMipmap mipmap = ToParamMipmap(levels, result.views);
  // What the fits came to, per level, in the index's metadata.
  const LafortuneMipSummary summary = SummarizeLafortuneMip(result);
  nlohmann::ordered_json meta =
      nlohmann::ordered_json::parse(mipmap.metadata_json);
  nlohmann::ordered_json fit;
  nlohmann::ordered_json per_level = nlohmann::ordered_json::array();
  for (const LafortuneLevelSummary& l : summary.levels) {
    nlohmann::ordered_json level;
    level["width"] = l.width;
    level["height"] = l.height;
    level["mean_relative_rms"] = l.mean_relative_rms;
    level["at_search_limit"] = l.at_search_limit;
    level["energy_scaled"] = l.energy_scaled;
    level["max_albedo"] = l.max_albedo;
    level["solve_fallback"] = l.solve_fallback;
    per_level.push_back(level);
  }
  fit["levels"] = per_level;
  fit["unusable"] = summary.unusable;
  fit["at_search_limit"] = summary.at_search_limit;
  fit["alternation_cap"] = summary.not_converged;
  fit["energy_scaled"] = summary.energy_scaled;
  if (!selection_json.empty()) {
    fit["selection"] = nlohmann::ordered_json::parse(selection_json);
  }
  meta["fit"] = fit;
  mipmap.metadata_json = meta.dump();
  return mipmap;
}

}  // namespace clothfit
