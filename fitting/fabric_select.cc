#include "fitting/fabric_select.h"

#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>

#include "fitting/cloth_fit.h"
#include "fitting/lafortune_mip.h"
#include "fitting/lafortune_select_internal.h"
#include "fitting/least_squares.h"
#include "fitting/thread_fit.h"
#include "io/input_error.h"
#include "io/text_util.h"
#include "models/presets.h"

namespace clothfit {
namespace {

struct Fitted {
  ModelParams params;
  FitReport report;
};

// A candidate family's fit of a table; `warm` (may be null) is its fit of
// the whole table, which a fold's fit starts from (one start, no search),
// holding the entries named in `held` at their values in `warm`
// (HeldInFolds).
struct Candidate {
  std::string description;
  std::function<Fitted(const MeasurementTable&, const ModelParams* warm,
                       const std::vector<std::string>& held)>
      fit;
};

std::vector<Candidate> Candidates(const FabricSelectOptions& options) {
  std::vector<Candidate> out;
  SolverOptions solver = options.solver;
  solver.progress = nullptr;
  for (int lobes = 0; lobes <= 2; ++lobes) {
    const std::string name = lobes == 0 ? "constant (Lambertian)"
                                        : "lafortune " + std::to_string(lobes) +
                                              " lobe(s), no lookup table";
    out.push_back({name, [=](const MeasurementTable& t, const ModelParams* warm,
                             const std::vector<std::string>&) {
                     LafortuneMipOptions o;
                     if (warm) o.fit.start = &std::get<LafortuneModel>(*warm);
                     o.fit.lobes = lobes;
                     o.fit.lookup_table = false;
                     o.fit.max_iterations = solver.max_iterations;
                     o.mip = false;
                     o.threads = 1;
                     o.noise = solver.noise;
                     const LafortuneFitResult r = FitLafortuneTable(t, o);
                     return Fitted{r.params, r.report};
                   }});
  }
  out.push_back(
      {"thread", [=](const MeasurementTable& t, const ModelParams* warm,
                     const std::vector<std::string>& held) {
         ThreadFitOptions o;
         if (warm) o.init = std::get<ThreadParams>(*warm);
         o.fix = held;
         o.solver = solver;
         o.fit_scale = options.fit_scale;
         // A fold holds the whole table's bound (scored, not written).
         o.energy_bound = options.energy_bound && !warm;
         const ThreadFitResult r = FitThread(t, o);
         return Fitted{r.params, r.report};
       }});
  struct ClothVariant {
    const char* preset;
    const char* label;
    std::vector<std::string> also_free;
    // The start search's weave geometries. The satin's design has three
    // dimensions (rotation, two offset scales) and 10 tangent samples a
    // row: on CUReT 128 points reached the relative rms of 512 within
    // 1.5 % on 9 of 11 fabrics (polyester zoomed and rug a 14 % and 7 %
    // higher; the satin was never the best variant), its whole-table fits
    // taking 4.9-8.6 s instead of 5.8-11.6 s (felt).
    int design_points = ClothFitOptions().design_points;
    // The solves of the best design points (with freedoms): the plain
    // weave's 8 are screened (ClothFitOptions::screen_iterations), the
    // satin's 4 solved in full (its rows, 10 tangent samples each, take
    // twice as long).
    int solve_starts = 8;
  };
  // The plain weave's freedoms (rotation, free offsets, a Lambertian term)
  // with free coverages or with a free eta per thread, 17 parameters for
  // one channel. Their common core alone (15) never had the lowest
  // held-out error on CUReT (docs/curet.md): both contain it.
  const std::vector<ClothVariant> variants = {
      {"linen_plain", "cloth plain", {}},
      {"polyester_satin_charmeuse", "cloth satin", {}},
      {"linen_plain",
       "cloth plain + rotation, offsets, diffuse, coverage",
       {"rotation_deg", "offsets_deg", "diffuse", "coverage"}},
      {"linen_plain",
       "cloth plain + rotation, offsets, diffuse, eta",
       {"rotation_deg", "offsets_deg", "diffuse", "eta"}},
      {"polyester_satin_charmeuse",
       "cloth satin + rotation, offset_scale, diffuse",
       {"rotation_deg", "offset_scale", "diffuse"},
       128,
       4},
  };
  for (const ClothVariant& v : variants) {
    ClothParams weave;
    GetPreset(v.preset, &weave);
    const ClothParams start = GenericClothStart(weave);
    out.push_back(
        {v.label, [=](const MeasurementTable& t, const ModelParams* warm,
                      const std::vector<std::string>& held) {
           ClothFitOptions o;
           o.fix = held;
           o.solver = solver;
           o.fit_scale = options.fit_scale;
           o.also_free = v.also_free;
           // A fold holds the whole table's bound (scored, not written).
           o.energy_bound = options.energy_bound && !warm;
           o.design_points = v.design_points;
           if (!v.also_free.empty()) o.solve_starts = v.solve_starts;
           if (warm) {  // the whole table's solution, solved again
             o.multi_start = false;
             o.solve_starts = 1;
             o.conserve_energy = false;  // scored, not written
           }
           ClothParams init = start;
           if (warm) {
             init = std::get<ClothParams>(*warm);
             init.scale = 1.0;  // fitted again with the others
           }
           const ClothFitResult r = FitCloth(t, init, o);
           return Fitted{r.params, r.report};
         }});
  }
  return out;
}

// The free parameters; of a one-channel table, the g and b entries that
// follow r are not counted (a Lafortune fit reports them free).
int FreeCount(const FitReport& r, int channels) {
  int n = 0;
  for (const ParameterReport& p : r.parameters) {
    const bool follows = channels == 1 && (text_util::EndsWith(p.name, "_g") ||
                                           text_util::EndsWith(p.name, "_b"));
    n += p.free && !follows ? 1 : 0;
  }
  return n;
}

// The free parameters at a bound that only limits the search, by name.
std::string AtLimits(const FitReport& r) {
  std::string out, dead;
  for (const ParameterReport& p : r.parameters) {
    if (p.at_search_limit && !p.no_effect) {
      out += (out.empty() ? "" : ", ") + p.name;
    }
    if (p.no_effect) dead += (dead.empty() ? "" : ", ") + p.name;
  }
  std::string note = out.empty() ? "" : "at a search limit: " + out;
  if (!dead.empty()) {
    note += (note.empty() ? "" : "; ") + std::string("no effect: ") + dead;
  }
  return note;
}

}  // namespace

std::vector<std::string> HeldInFolds(const FitReport& r) {
  std::vector<std::string> held;
  int free = 0;
  for (const ParameterReport& p : r.parameters) {
    // The fits free the scale after --fix (it is not theirs to fix).
    free += p.free && p.name != kFitScale.name ? 1 : 0;
    if (p.free && (p.no_effect || p.at_bound)) held.push_back(p.name);
  }
  // Every entry held would leave a fold nothing to fit.
  if (static_cast<int>(held.size()) == free) held.clear();
  return held;
}

FabricSelection SelectFabricModel(const MeasurementTable& table_in,
                                  const FabricSelectOptions& options_in) {
  if (table_in.quantity == Quantity::kTransmittance) {
    throw InputError(table_in.source +
                     ": --model auto chooses among reflection models; the "
                     "table holds transmittance");
  }
  if (options_in.folds < 2) {
    throw InputError("--folds: must be at least 2");
  }
  // Reflection rows only: every candidate predicts those.
  MeasurementTable table = table_in;
  table.rows.clear();
  for (const TableRow& row : table_in.rows) {
    if (IsReflectionRow(row)) table.rows.push_back(row);
  }
  const int folds = options_in.folds;
  if (static_cast<int>(table.rows.size()) < 2 * folds) {
    throw InputError(table_in.source + ": --model auto with " +
                     std::to_string(folds) + " folds needs at least " +
                     std::to_string(2 * folds) + " reflection rows, got " +
                     std::to_string(table.rows.size()));
  }
  // The score is RMS(model - data) / RMS(data): without a sigma column or
  // a chosen noise model, every candidate minimises exactly that.
  FabricSelectOptions options = options_in;
  if (options.solver.noise.kind == NoiseKind::kDefault && !table.has_sigma) {
    options.solver.noise.kind = NoiseKind::kAbsolute;
  }
  std::vector<int> fold(table.rows.size());
  for (size_t i = 0; i < fold.size(); ++i)
    fold[i] = static_cast<int>(i % folds);

  const std::vector<Candidate> candidates = Candidates(options);
  FabricSelection out;
  std::vector<Fitted> whole(candidates.size());
  double best = HUGE_VAL;
  bool best_converged = false;
  for (size_t c = 0; c < candidates.size(); ++c) {
    if (options.progress) {
      options.progress("candidate " + std::to_string(c + 1) + " of " +
                       std::to_string(candidates.size()) + ": " +
                       candidates[c].description);
    }
    CandidateReport report;
    report.description = candidates[c].description;
    report.samples = -1;
    const auto t0 = std::chrono::steady_clock::now();
    try {
      whole[c] = candidates[c].fit(table, nullptr, {});
    } catch (const InputError& e) {
      report.note = e.what();
      out.selection.candidates.push_back(report);
      continue;
    }
    report.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0)
            .count();
    const FitReport& r = whole[c].report;
    report.usable = r.usable;
    report.converged = r.converged;
    report.free_parameters = FreeCount(r, table.channels);
    report.note = AtLimits(r);
    double se = 0.0, ss = 0.0;
    int n = 0;
    AddFoldErrors(
        table, fold, -1, [&](size_t) { return &whole[c].params; }, &se, &ss,
        &n);
    SetTrainingScores(se, ss, n, &report);
    // Held out: each fold's rows predicted by the fit of the others.
    double hse = 0.0, hss = 0.0;
    bool all_folds = r.usable;
    const std::vector<std::string> held = HeldInFolds(r);
    for (int f = 0; f < folds && all_folds; ++f) {
      Fitted part;
      try {
        part = candidates[c].fit(WithoutFold(table, fold, f), &whole[c].params,
                                 held);
      } catch (const InputError&) {
        all_folds = false;
        break;
      }
      all_folds = part.report.usable;
      AddFoldErrors(
          table, fold, f, [&](size_t) { return &part.params; }, &hse, &hss,
          nullptr);
    }
    if (all_folds && hss > 0.0) {
      report.heldout_relative_rms = std::sqrt(hse / hss);
      const bool better = (report.converged && !best_converged) ||
                          (report.converged == best_converged &&
                           report.heldout_relative_rms < best);
      if (better) {
        best = report.heldout_relative_rms;
        best_converged = report.converged;
        out.selection.chosen = static_cast<int>(c);
      }
    }
    out.selection.candidates.push_back(report);
  }
  if (out.selection.chosen < 0) {
    throw InputError(table_in.source +
                     ": --model auto: no candidate could be fitted to every "
                     "fold");
  }
  const size_t chosen = static_cast<size_t>(out.selection.chosen);
  std::ostringstream reason;
  reason << candidates[chosen].description << ": the lowest held-out relative "
         << "rms (" << folds << "-fold over rows) among the candidates whose "
         << (best_converged ? "fit converged"
                            : "fit was usable (none converged)");
  out.selection.reason = reason.str();
  out.params = whole[chosen].params;
  out.report = whole[chosen].report;
  out.report.rows_not_used =
      static_cast<int>(table_in.rows.size() - table.rows.size());
  return out;
}

}  // namespace clothfit
