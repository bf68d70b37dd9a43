#include "fitting/cloth_fit.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>

#include "fitting/cloth_search.h"
#include "fitting/cloth_weave_internal.h"
#include "fitting/energy.h"
#include "fitting/energy_bound_fit_internal.h"
#include "fitting/least_squares.h"
#include "fitting/model_residual_internal.h"
#include "fitting/start_search.h"
#include "io/input_error.h"
#include "io/text_util.h"
#include "models/evaluate.h"

namespace clothfit {

ClothParams GenericClothStart(const ClothParams& weave) {
  ClothParams c = weave;
  for (ClothThread& th : c.threads) {
    th.params.kd = 0.3;
    th.params.gamma_s_deg = 10.0;
    th.params.gamma_v_deg = 20.0;
    th.params.albedo = glm::dvec3(0.1);
  }
  return c;
}

std::vector<std::string> ClothParameterNames(const ClothParams& layout) {
  std::vector<std::string> names;
  for (const ParameterSpec& s : ClothSpecs(layout)) names.push_back(s.name);
  return names;
}

std::vector<double> ClothParameterValues(const ClothParams& c,
                                         const ClothParams& layout) {
  // c's samples where it has the layout's counts, else the layout's.
  ClothParams shaped = c;
  for (size_t j = 0; j < shaped.threads.size() && j < layout.threads.size();
       ++j) {
    if (shaped.threads[j].offsets_deg.size() !=
        layout.threads[j].offsets_deg.size()) {
      shaped.threads[j].offsets_deg = layout.threads[j].offsets_deg;
    }
  }
  std::vector<double> x = ClothToVector(shaped);
  const ClothVector v(shaped);
  for (size_t j = 0; j < c.threads.size() && j < layout.threads.size(); ++j) {
    double mine = 0.0, theirs = 0.0;
    for (double o : shaped.threads[j].offsets_deg) {
      mine = std::max(mine, std::abs(o));
    }
    for (double o : layout.threads[j].offsets_deg) {
      theirs = std::max(theirs, std::abs(o));
    }
    // offset_scale is the ratio of the largest offsets; the entries are
    // the offsets it scales.
    const double ratio = theirs > 0.0 ? mine / theirs : 1.0;
    x[v.OffsetScale(j)] = ratio;
    for (size_t k = 0; k < v.Offsets(j) && ratio > 0.0; ++k) {
      x[v.Offset(j, k)] /= ratio;
    }
  }
  return x;
}

namespace {

// The cloth a solution x writes: of a one-channel table, the g and b of
// the albedos and the diffuse term follow r.
ClothParams WrittenCloth(const Weave& weave, const std::vector<double>& x,
                         int channels) {
  ClothParams c = ClothFromVector(weave, ReportedVector(weave, x));
  if (channels == 1) {
    for (ClothThread& th : c.threads) {
      th.params.albedo = glm::dvec3(th.params.albedo.x);
    }
    c.diffuse = glm::dvec3(c.diffuse.x);
  }
  return c;
}

// Whether entry i moves the tangent samples (the rotation, a thread's
// offset_scale or offsets).
bool IsGeometry(const ClothVector& v, size_t i) {
  if (i == v.Rotation()) return true;
  for (size_t j = 0; j < v.Threads(); ++j) {
    if (i >= v.OffsetScale(j) && i < v.Offset(j, v.Offsets(j))) return true;
  }
  return false;
}

// Each start solved first with its geometry held (the samples then never
// change: a fast and well-conditioned solve of the widths, albedos, kd,
// coverages, diffuse, scale), then ranked by that cost. From a start's
// geometry with the other entries far off, a solve with everything free
// stalls: the narrow lobes' derivatives in the offsets and rotation make
// Levenberg-Marquardt's steps tiny and it stops at the function tolerance
// (a satin weave on a linen table: relative rms 3.7 with offset_scale
// free, 0.92 with it fixed).
std::vector<std::vector<double>> RefineAtFixedGeometry(
    const MeasurementTable& table, const Weave& weave,
    const std::vector<ParameterSpec>& specs, const ClothFitOptions& options,
    const std::vector<std::vector<double>>& starts) {
  const ClothVector& v = weave.vector;
  ClothFitOptions held;
  held.solver = options.solver;
  held.solver.progress = nullptr;
  held.multi_start = false;
  held.solve_starts = 1;
  held.shared_albedo = options.shared_albedo;
  held.fit_scale = options.fit_scale;
  held.energy_bound = false;  // the paper's model at the start's geometry
  // A start, not a result: the energy check (a quadrature, about as long as
  // the held solve) waits for the solves from it.
  held.conserve_energy = false;
  for (size_t i = 0; i < specs.size(); ++i) {
    if (specs[i].free && !IsGeometry(v, i) && i != v.Scale()) {
      held.free_only.push_back(specs[i].name);
    }
  }
  if (held.free_only.empty()) return starts;  // nothing but the geometry
  std::vector<std::pair<double, std::vector<double>>> ranked;
  for (const std::vector<double>& start : starts) {
    const ClothParams at = ClothFromVector(weave, ReportedVector(weave, start));
    const ClothFitResult r = FitCloth(table, at, held);
    if (!r.report.usable) {
      ranked.push_back({HUGE_VAL, start});
      continue;
    }
    // Back into the solver's coordinates, the start's geometry kept.
    std::vector<double> x = ReportedVector(weave, start);
    const std::vector<double> solved = ClothToVector(r.params);
    const ClothVector u(r.params);
    for (size_t j = 0; j < v.Threads(); ++j) {
      std::copy(solved.begin() + u.Thread(j),
                solved.begin() + u.Thread(j) + kThreadFlatSize,
                x.begin() + v.Thread(j));
      x[v.Coverage(j)] = solved[u.Coverage(j)];
    }
    for (int c = 0; c < 3; ++c) x[v.Diffuse(c)] = solved[u.Diffuse(c)];
    x[v.Scale()] = r.params.scale;
    ranked.push_back({r.report.final_cost, CoverageToStick(weave, x)});
  }
  std::stable_sort(
      ranked.begin(), ranked.end(),
      [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<std::vector<double>> out;
  for (auto& [cost, x] : ranked) out.push_back(std::move(x));
  return out;
}

// One fit of the model through the rows' fixed bound factors (null: the
// paper's model), or (`plan`) of the bounded model with its tables through
// that plan: from the start search, from the solver vector `*refit_x`
// alone, or from both when `search_bound` is given (whose factors of the
// rows the search sees); a fitted scale at most scale_cap. The solver vector of
// the result goes to `*x_out` (when not null).
ClothFitResult FitClothThrough(
    const MeasurementTable& table, const ClothParams& init,
    const ClothFitOptions& options, const std::vector<double>* bound_factor,
    const std::vector<double>* refit_x, std::vector<double>* x_out,
    const EnergyBoundPlan* plan = nullptr,
    const EnergyBound* search_bound = nullptr, double scale_cap = HUGE_VAL) {
  const size_t n = init.threads.size();
  auto weave = std::make_shared<Weave>(init);
  const ClothVector& v = weave->vector;
  LeastSquaresProblem lsq;
  lsq.specs = ClothSpecs(init);
  // With freedoms asked for, --fix waits for them: fixing the whole default
  // set while a freedom stays free is a fit (fit --model auto's folds hold
  // entries so, fitting/fabric_select.h HeldInFolds).
  ApplyFreeFix(
      options.also_free.empty() ? options.fix : std::vector<std::string>(),
      options.free_only, &lsq.specs);
  FreeAlso(options.also_free, &lsq.specs);
  ApplyFreeFix(options.fix, {}, &lsq.specs);  // --fix wins over both
  // A thread whose offsets are all 0 has nothing for offset_scale to
  // scale.
  for (size_t j = 0; j < n; ++j) {
    bool flat = true;
    for (double o : init.threads[j].offsets_deg) flat = flat && o == 0.0;
    if (flat) lsq.specs[v.OffsetScale(j)].free = false;
  }
  auto is_free = [&](size_t i) { return lsq.specs[i].free; };
  for (size_t j = 0; j < n; ++j) {
    bool offset_free = false;
    for (size_t k = 0; k < v.Offsets(j); ++k) {
      offset_free = offset_free || is_free(v.Offset(j, k));
    }
    if (offset_free && is_free(v.OffsetScale(j))) {
      throw InputError(ClothThreadPrefix(j) +
                       "offset_scale and offsets_deg: free one or the other "
                       "(the scale multiplies the offsets)");
    }
  }
  if (table.channels == 1) {  // one channel: g and b follow r
    for (size_t j = 0; j < n; ++j) {
      lsq.specs[v.Thread(j) + 5].free = false;
      lsq.specs[v.Thread(j) + 6].free = false;
    }
    lsq.specs[v.Diffuse(1)].free = lsq.specs[v.Diffuse(2)].free = false;
  }
  weave->shared_albedo = options.shared_albedo && n > 1;
  if (weave->shared_albedo) {  // threads j > 0 take thread 0's albedo
    for (size_t j = 1; j < n; ++j) {
      for (int c = 0; c < 3; ++c) lsq.specs[v.Thread(j) + 4 + c].free = false;
    }
  }
  // The geometry (rotation, offsets) fixed: the tangent samples never
  // change. eta fixed: nor do their Fresnel terms.
  bool geometry_fixed = true;
  for (size_t i = 0; i < lsq.specs.size(); ++i) {
    geometry_fixed = geometry_fixed && !(is_free(i) && IsGeometry(v, i));
  }
  std::vector<bool> eta_fixed(n);
  double fixed_coverage = 0.0;
  for (size_t j = 0; j < n; ++j) {
    eta_fixed[j] = !is_free(v.Thread(j));
    if (is_free(v.Coverage(j))) {
      weave->stick.push_back(j);
    } else {
      fixed_coverage += init.threads[j].coverage;
    }
  }
  weave->remaining = std::max(0.0, 1.0 - fixed_coverage);
  lsq.reported = [weave](const std::vector<double>& x) {
    return ReportedVector(*weave, x);
  };
  lsq.block_sizes = v.BlockSizes();
  lsq.specs[v.Scale()].free = options.fit_scale;
  lsq.specs[v.Scale()].upper = std::min(lsq.specs[v.Scale()].upper, scale_cap);
  const Weighting weighting(table, options.solver.noise);
  lsq.sigma_known = weighting.LevelKnown();

  auto evaluator = std::make_shared<ClothEvaluator>();
  evaluator->table = &table;
  evaluator->weave = weave;
  evaluator->bound_factor = bound_factor;
  evaluator->geometry_fixed = geometry_fixed;
  evaluator->eta_fixed = eta_fixed;
  if (geometry_fixed && table.rows.size() <= options.held_sample_rows) {
    evaluator->samples.resize(table.rows.size());
    for (size_t i = 0; i < table.rows.size(); ++i) {
      evaluator->samples[i] = std::make_shared<const RowSamples>(
          ComputeRowSamples(init, eta_fixed, table.rows[i]));
    }
  }
  ResidualBlocks blocks;
  for (int b = 0; b <= v.ClothBlock(); ++b) blocks.used.push_back(b);
  if (options.fit_scale) {
    blocks.scale = static_cast<int>(blocks.used.size());
    blocks.used.push_back(v.ScaleBlock());
  }
  SetModelResiduals(std::shared_ptr<const ClothEvaluator>(evaluator),
                    TableFitRows(table, weighting), blocks, &lsq, plan);
  // The fit writes a cloth that conserves energy (scaled down if need
  // be): among the starts' solutions, one that conserves energy as it
  // stands wins over a lower cost that would be scaled down.
  const bool conserve =
      options.conserve_energy && !options.energy_bound && !bound_factor;
  if (conserve) {
    lsq.plausible = [weave,
                     channels = table.channels](const std::vector<double>& x) {
      const ClothParams c = WrittenCloth(*weave, x, channels);
      return ModelEnergy(ModelParams(c)).max_albedo <= 1.0;
    };
  }

  // Starts (fitting/cloth_search.h): the widths and linear entries by a
  // grid and closed form, over a space-filling design of the geometry and
  // eta where those are free; then the solver from the best, until the
  // best cost has been reached `stop_after_hits` times.
  // The search and the held-geometry solves see the rows the starts are
  // solved on.
  MeasurementTable sample_storage;
  const MeasurementTable& sample = SearchTable(table, &sample_storage);
  ClothStartProblem search;
  search.table = &sample;
  search.weighting = &weighting;
  search.weave = weave.get();
  search.specs = &lsq.specs;
  search.init = CoverageToStick(*weave, ClothToVector(init));
  search.row_factor = search_bound
                          ? EnergyBoundFactors(sample, search_bound)
                          : SearchRowValues(table.rows.size(), bound_factor);
  search.search_widths = options.multi_start;
  search.design_points = options.multi_start ? options.design_points : 0;
  ClothStarts starts;
  const bool searched = !refit_x || search_bound;
  if (searched) {
    starts = SearchClothStarts(search, std::max(1, options.solve_starts));
  }
  if (starts.design_points > 1) {
    lsq.stop_after_hits = options.stop_after_hits;
    lsq.screen_iterations = options.screen_iterations;
    lsq.screen_keep = options.screen_keep;
  }
  if (!geometry_fixed && searched) {
    starts.starts = RefineAtFixedGeometry(sample, *weave, lsq.specs, options,
                                          starts.starts);
  }
  if (refit_x) starts.starts.insert(starts.starts.begin(), *refit_x);

  ClothFitResult result;
  std::vector<double> x = starts.starts.front();
  result.report = SolveLeastSquares(lsq, starts.starts, options.solver, &x);
  if (starts.design_points > 1) {
    result.report.search = std::to_string(starts.design_points) +
                           " weave geometries searched; " +
                           result.report.search;
  }
  ReportWeighting(weighting, &result.report);
  result.params = WrittenCloth(*weave, x, table.channels);
  result.report.rows = static_cast<int>(table.rows.size());
  if (weave->shared_albedo) {  // report the tied albedos at their value
    for (ParameterReport& p : result.report.parameters) {
      for (const char* channel : {"albedo_r", "albedo_g", "albedo_b"}) {
        if (text_util::EndsWith(p.name, std::string(".") + channel)) {
          p.value = x[4 + (channel[7] == 'r' ? 0 : channel[7] == 'g' ? 1 : 2)];
        }
      }
    }
  }
  if (table.channels == 1) {
    ReportChannelsFollowRed("albedo", &result.report);
    ReportChannelsFollowRed("diffuse", &result.report);
  }
  if (conserve) {
    ConserveEnergyByScale(
        ModelParams(result.params),
        [&](const std::function<void(double, double)>& visit) {
          lsq.predict(x, [&](double model, double measured, const TableRow*) {
            visit(model, measured);
          });
        },
        &result.params.scale, &result.report);
  }
  if (x_out) *x_out = x;
  return result;
}

}  // namespace

ClothFitResult FitCloth(const MeasurementTable& table, const ClothParams& given,
                        const ClothFitOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();  // search + solves
  // The search and the solves fit the paper's model (the bound, if any, is
  // the fit's to find): an init's bound is dropped.
  ClothParams init = given;
  init.energy_bound = nullptr;
  RequireWeightedRows(table);
  if (table.quantity == Quantity::kTransmittance) {
    throw InputError(
        "a cloth model predicts brdf or cosine_weighted values, "
        "not transmittance");
  }
  if (init.threads.empty() || init.threads.size() > 3) {
    throw InputError(
        "cloth fit: the initial parameters need 1 to 3 threads, got " +
        std::to_string(init.threads.size()));
  }
  // The cloth model is reflection only (docs/models.md): a row with the light
  // or the view below the surface tells nothing about it. Such rows are left
  // out and counted, not fitted as zeros.
  const int not_reflection = CountNotReflection(table, "cloth");
  if (not_reflection > 0) {
    MeasurementTable reflection = table;
    reflection.rows.erase(
        std::remove_if(
            reflection.rows.begin(), reflection.rows.end(),
            [](const TableRow& row) { return !IsReflectionRow(row); }),
        reflection.rows.end());
    ClothFitResult result = FitCloth(reflection, given, options);
    result.report.rows_not_used = not_reflection;
    return result;
  }
  ClothFitResult result;
  if (options.energy_bound) {
    // The solver's vector of each first fit: the bounded solves start from
    // the chosen one's.
    std::vector<double> x_every, x_within;
    BoundedStart<ClothParams> start = ChooseBoundedStart<ClothParams>(
        table, options.solver.noise,
        [&](const MeasurementTable& rows, bool every) {
          return FitClothThrough(rows, init, options, nullptr, nullptr,
                                 every ? &x_every : &x_within);
        });
    std::vector<double> x = start.of_every_row ? x_every : x_within;
    result = SettleEnergyBound<ClothParams>(
        table,
        [&](const EnergyBoundPlan& plan, const ClothParams&,
            const EnergyBound* search_bound, double scale_cap) {
          return FitClothThrough(table, init, options, nullptr, &x, &x, &plan,
                                 search_bound, scale_cap);
        },
        std::move(start));
  } else {
    // The init's bound held: its factors fixed, and carried by the result.
    const std::vector<double> factors =
        given.energy_bound ? EnergyBoundFactors(table, given.energy_bound.get())
                           : std::vector<double>();
    result = FitClothThrough(table, init, options,
                             given.energy_bound ? &factors : nullptr, nullptr,
                             nullptr);
    result.params.energy_bound = given.energy_bound;
  }
  result.report.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0)
          .count();
  return result;
}

}  // namespace clothfit
