#include "bench/stability.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <sstream>

#include "bench/holes_problem.h"
#include "charts/chart.h"
#include "data_synthetic/holes_truth.h"
#include "data_synthetic/synthetic_table.h"
#include "fitting/cloth_fit.h"
#include "fitting/holes_fit.h"
#include "fitting/slab_fit.h"
#include "fitting/thread_fit.h"
#include "io/atomic_file.h"
#include "io/text_util.h"
#include "models/presets.h"

namespace clothfit {
namespace {

// One data set of a stability run: the table and where the truth is
// compared.
struct Trial {
  MeasurementTable table;
  std::vector<TableRow> held_out;
};

// The levels of one knob and how each changes the data or the start.
struct Knob {
  std::string name;
  std::vector<double> levels;
  std::function<std::string(double)> label;
};

// Held-out error; a fit without any (no truth signal) counts as a failure.
double Error(const ModelParams& fitted, const ModelParams& truth,
             const std::vector<TableRow>& rows) {
  const double e = HeldOutError(fitted, truth, rows, Quantity::kBrdf);
  return std::isnan(e) ? HUGE_VAL : e;
}

// Rows of a hemisphere sample: all (coverage 90), theta <= level (near
// normal) or, for a negative level, both theta >= -level (grazing only).
std::vector<TableRow> Coverage(std::vector<TableRow> rows, double level) {
  const double c = std::cos(Radians(std::abs(level)));
  std::vector<TableRow> kept;
  for (const TableRow& r : rows) {
    const bool near = r.wi.z >= c && std::abs(r.wo.z) >= c;
    const bool grazing = r.wi.z <= c && std::abs(r.wo.z) <= c;
    if (level >= 90.0 || (level > 0.0 ? near : grazing)) kept.push_back(r);
  }
  return kept;
}

Trial MakeTrial(const ModelParams& truth, bool thread, const std::string& knob,
                double level, int rows, uint64_t seed) {
  Random random(seed);
  DirectionSampling sampling;
  sampling.full_sphere_out = thread;
  const bool coverage = knob == "coverage";
  // Restricted coverage keeps a part of a larger sample: as many rows.
  sampling.rows = coverage && level < 90.0 ? rows * 8 : rows;
  Trial trial;
  trial.table.quantity = Quantity::kBrdf;
  trial.table.rows = SampleDirections(sampling, &random);
  if (coverage) trial.table.rows = Coverage(trial.table.rows, level);
  if (static_cast<int>(trial.table.rows.size()) > rows) {
    trial.table.rows.resize(rows);
  }
  SynthOptions synth;
  synth.noise = knob == "noise" ? level : 0.02;
  SynthesizeValues(truth, synth, &random, &trial.table);
  if (knob == "outliers") {  // gross errors: x 10 on a fraction of rows
    for (TableRow& r : trial.table.rows) {
      if (random.Uniform() < level) r.value *= 10.0;
    }
  }
  sampling.rows = 500;
  trial.held_out = SampleDirections(sampling, &random);
  return trial;
}

// The start `factor` away from the truth: widths x factor, albedo x factor
// (capped at 1), kd towards 0.5.
ThreadParams FarThread(ThreadParams p, double factor) {
  p.gamma_s_deg = std::min(p.gamma_s_deg * factor, 60.0);
  p.gamma_v_deg = std::min(p.gamma_v_deg * factor, 90.0);
  p.albedo = glm::min(p.albedo * factor, glm::dvec3(1.0));
  p.kd = factor > 1.0 ? 0.5 : p.kd;
  return p;
}

// One holes run (fitting/holes_fit.h): a random mask (half opaque, one per
// seed), columns 0.8 texels high (wall colour 0.3 when it is fitted), the
// model's transmittance (the extension at the top level, the fit's
// default: the study tests the fit, not the model against ray tracing,
// which `bench` measures) at views theta 0-70 deg x 4 azimuths (restricted
// by the coverage knob) with 2 % noise unless the noise is the knob; held
// out: 4 other azimuths at theta 5-65 deg. Returns the held-out error;
// *ok: exit status 0.
double HolesRun(const std::string& knob, double level, bool wall, Loss loss,
                bool quick, uint64_t seed, bool* ok) {
  const int size = quick ? 16 : 32;
  const Mask mask = RandomMask(size, size, 0.5, seed);
  const HoleTexture texture = AnalyzeMask(mask, true);
  HolesParams truth;
  truth.thickness_texels = 0.8;
  if (wall) truth.wall_color = glm::dvec3(0.3);
  std::vector<double> thetas;
  for (double theta = 0.0; theta <= 70.0; theta += 10.0) {
    const bool keep = knob != "coverage" || level >= 90.0 ||
                      (level > 0.0 ? theta <= level : theta >= -level);
    if (keep) thetas.push_back(theta);
  }
  const HolesTile tile = HolesTileOf(texture);  // the fit's defaults
  MeasurementTable table =
      HolesModelTable(tile, truth, thetas, {0.0, 90.0, 180.0, 270.0});
  const MeasurementTable held_out = HolesModelTable(
      tile, truth, {5.0, 25.0, 45.0, 65.0}, {45.0, 135.0, 225.0, 315.0});
  Random random(seed);
  const double noise = knob == "noise" ? level : 0.02;
  for (TableRow& r : table.rows) {
    r.value *= std::max(0.0, 1.0 + noise * random.Normal());
    if (knob == "outliers" && random.Uniform() < level) r.value *= 10.0;
  }
  HolesFitOptions fit;
  fit.solver.loss = loss;
  fit.fit_wall_color = wall;
  if (knob == "start_distance") {  // thickness x factor from the truth
    HolesParams start;
    start.thickness_texels = truth.thickness_texels * level;
    fit.init = start;
  }  // else the fit's own start (HolesParams(), and its grid), as a user's
  const HolesFitResult r = FitHoles(table, tile, fit);
  *ok = r.report.usable && r.report.converged;
  const double e = HolesHeldOutError(r.params, tile, held_out);
  return std::isnan(e) ? HUGE_VAL : e;
}

}  // namespace

std::vector<StabilityRow> RunStability(const BenchOptions& options) {
  ClothParams satin;
  GetPreset("polyester_satin_charmeuse", &satin);
  const ThreadParams thread = satin.threads[0].params;
  const int seeds = options.quick ? 2 : 5;
  const int thread_rows = options.quick ? 300 : 2000;
  const int cloth_rows = options.quick ? 200 : 1500;
  auto percent = [](double v) {
    return text_util::FormatNumber(100.0 * v) + " %";
  };
  const std::vector<Knob> knobs = {
      {"noise", {0.0, 0.02, 0.05, 0.1, 0.2, 0.4}, percent},
      {"start_distance",
       {1.0, 2.0, 4.0, 8.0},
       [](double v) { return "x" + text_util::FormatNumber(v); }},
      {"coverage",
       {90.0, 60.0, 30.0, -60.0},
       [](double v) {
         return v >= 90.0 ? std::string("full")
                : v > 0.0 ? "theta <= " + text_util::FormatNumber(v)
                          : "theta >= " + text_util::FormatNumber(-v);
       }},
      {"outliers", {0.0, 0.01, 0.05, 0.1, 0.2}, percent},
  };
  // The slab: tau 0.05, albedo (0.4, 0.3, 0.2), inside its regime.
  const SlabParams slab = BenchSlabTruth();
  enum class Kind { kThread, kCloth, kSlab, kHoles, kHolesWall };
  struct Fitter {
    std::string name;
    Kind kind;
    Loss loss;
  };
  std::vector<Fitter> fitters = {
      {"thread", Kind::kThread, Loss::kNone},
      {"thread+cauchy", Kind::kThread, Loss::kCauchy},
      {"slab", Kind::kSlab, Loss::kNone},
      {"holes", Kind::kHoles, Loss::kNone},
      {"holes+cauchy", Kind::kHoles, Loss::kCauchy},
      {"holes+wall", Kind::kHolesWall, Loss::kNone}};
  // The cloth fit takes seconds: not in the quick study.
  if (!options.quick) fitters.push_back({"cloth", Kind::kCloth, Loss::kNone});
  std::vector<StabilityRow> out;
  for (const Knob& knob : knobs) {
    for (const Fitter& fitter : fitters) {
      // The robust loss only matters for outliers.
      if (fitter.loss != Loss::kNone && knob.name != "outliers") continue;
      // --models: "holes" stands for "holes+wall" and "holes+cauchy" too.
      const std::string base = fitter.name.substr(0, fitter.name.find('+'));
      if (!options.models.empty() &&
          std::find(options.models.begin(), options.models.end(), base) ==
              options.models.end()) {
        continue;
      }
      for (double level : knob.levels) {
        if (options.progress) {
          options.progress("stability: " + fitter.name + " " + knob.name + " " +
                           knob.label(level));
        }
        StabilityRow row;
        row.fitter = fitter.name;
        row.knob = knob.name;
        row.level = level;
        row.level_label = knob.label(level);
        std::vector<double> errors;
        for (int s = 0; s < seeds; ++s) {
          const uint64_t seed = options.seed * 1000 + 17 * s;
          const ModelParams truth =
              fitter.kind == Kind::kCloth  ? ModelParams(satin)
              : fitter.kind == Kind::kSlab ? ModelParams(slab)
                                           : ModelParams(thread);
          const bool holes =
              fitter.kind == Kind::kHoles || fitter.kind == Kind::kHolesWall;
          // Thread and slab tables have wo over the whole sphere.
          const Trial trial =
              holes
                  ? Trial()
                  : MakeTrial(
                        truth, fitter.kind != Kind::kCloth, knob.name, level,
                        fitter.kind == Kind::kCloth ? cloth_rows : thread_rows,
                        seed);
          const double factor = knob.name == "start_distance" ? level : 1.0;
          bool ok = false;
          double error = HUGE_VAL;
          if (holes) {
            error = HolesRun(knob.name, level, fitter.kind == Kind::kHolesWall,
                             fitter.loss, options.quick, seed, &ok);
          } else if (fitter.kind == Kind::kSlab) {
            SlabFitOptions fit;
            fit.solver.loss = fitter.loss;
            SlabParams start = slab;  // tau and albedo x factor
            start.tau *= factor;
            start.albedo = glm::min(start.albedo * factor, glm::dvec3(1.0));
            fit.init = start;
            const SlabFitResult r = FitSlab({trial.table}, fit);
            ok = r.report.usable && r.report.converged;
            error = Error(r.params, slab, trial.held_out);
          } else if (fitter.kind == Kind::kCloth) {
            ClothParams start = GenericClothStart(satin);
            for (ClothThread& t : start.threads) {
              t.params = FarThread(t.params, factor);
            }
            ClothFitOptions fit;
            fit.energy_bound = false;  // the table is the paper's model
            fit.solver.loss = fitter.loss;
            const ClothFitResult r = FitCloth(trial.table, start, fit);
            ok = r.report.usable && r.report.converged;
            error = Error(r.params, satin, trial.held_out);
          } else {
            ThreadFitOptions fit;
            fit.energy_bound = false;  // the table is the paper's model
            fit.solver.loss = fitter.loss;
            fit.init = FarThread(thread, factor);
            const ThreadFitResult r = FitThread(trial.table, fit);
            ok = r.report.usable && r.report.converged;
            error = Error(r.params, thread, trial.held_out);
          }
          ++row.runs;
          row.successes += ok && error < kStabilitySuccessError;
          errors.push_back(error);
        }
        std::sort(errors.begin(), errors.end());
        row.median_error = errors[errors.size() / 2];
        out.push_back(row);
      }
    }
  }
  return out;
}

std::vector<std::string> WriteStabilityReport(
    const std::vector<StabilityRow>& rows, const std::string& dir) {
  std::vector<std::string> files;
  std::ostringstream csv, md;
  csv << "fitter,knob,level,level_label,runs,successes,median_error\n";
  md << "# Stability\n\nSuccess: exit status 0 and a held-out relative RMS "
        "error below "
     << kStabilitySuccessError << " (docs/bench.md names the failure modes).\n";
  std::vector<std::string> knobs;
  for (const StabilityRow& r : rows) {
    csv << r.fitter << "," << r.knob << "," << text_util::FormatNumber(r.level)
        << ",\"" << r.level_label << "\"," << r.runs << "," << r.successes
        << "," << text_util::FormatNumber(r.median_error) << "\n";
    if (std::find(knobs.begin(), knobs.end(), r.knob) == knobs.end()) {
      knobs.push_back(r.knob);
    }
  }
  WriteFileAtomically(dir + "/stability.csv", csv.str());
  files.push_back(dir + "/stability.csv");
  for (const std::string& knob : knobs) {
    ScatterChart chart;
    chart.title = "success rate against " + knob;
    chart.x_label = knob + " (level index; labels in the table)";
    chart.y_label = "success rate (fraction of the runs)";
    // A fraction: the whole of [0, 1], a little room above for the labels.
    chart.y_min = 0.0;
    chart.y_max = 1.08;
    std::map<std::string, size_t> series;
    md << "\n## " << knob << "\n\n![" << knob << "](stability_" << knob
       << ".png)\n\n| fitter | level | successes | median error |\n"
          "|---|---|---|---|\n";
    std::map<std::string, int> index;
    for (const StabilityRow& r : rows) {
      if (r.knob != knob) continue;
      auto [it, added] = series.emplace(r.fitter, chart.series.size());
      if (added) {
        chart.series.push_back(ScatterSeries());
        chart.series.back().name = r.fitter;
        chart.series.back().lines = true;
      }
      ChartPoint p;
      p.x = index[r.fitter]++;
      p.y = r.runs ? static_cast<double>(r.successes) / r.runs : 0.0;
      p.label = r.level_label;
      chart.series[it->second].points.push_back(p);
      md << "| " << r.fitter << " | " << r.level_label << " | " << r.successes
         << "/" << r.runs << " | " << text_util::FormatNumber(r.median_error)
         << " |\n";
    }
    const std::string png = dir + "/stability_" + knob + ".png";
    WriteScatterChartPng(chart, png);
    files.push_back(png);
  }
  WriteFileAtomically(dir + "/stability.md", md.str());
  files.push_back(dir + "/stability.md");
  return files;
}

}  // namespace clothfit
