#include "bench/bench.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "bench/bench_charts.h"
#include "bench/bench_internal.h"
#include "charts/chart.h"
#include "io/atomic_file.h"
#include "io/text_util.h"

namespace clothfit {
namespace {

using namespace bench_internal;  // NOLINT: the bench's own internals

bool Wanted(const BenchOptions& o, const std::string& model) {
  return o.models.empty() ||
         std::find(o.models.begin(), o.models.end(), model) != o.models.end();
}

// A CSV field: empty where the figure does not apply (a model without a
// size), never "nan".
std::string Number(double v) {
  return std::isfinite(v) ? text_util::FormatNumber(v) : "";
}

// Four significant digits, for the summary's tables.
std::string Short(double v) {
  return std::isfinite(v) ? text_util::FormatNumber(v, 4) : "n/a";
}

}  // namespace

SlabParams BenchSlabTruth() {
  SlabParams p;
  p.tau = glm::dvec3(0.05);
  p.albedo = glm::dvec3(0.4, 0.3, 0.2);
  return p;
}

double HeldOutError(const ModelParams& fitted, const ModelParams& truth,
                    const std::vector<TableRow>& rows, Quantity q) {
  double se = 0.0, ss = 0.0;
  for (const TableRow& row : rows) {
    const glm::dvec3 a = Evaluate(fitted, row.wi, row.wo, q);
    const glm::dvec3 b = Evaluate(truth, row.wi, row.wo, q);
    se += glm::dot(a - b, a - b);
    ss += glm::dot(b, b);
  }
  return ss > 0.0 ? std::sqrt(se / ss) : kNaN;
}

std::vector<BenchRow> RunBench(const BenchOptions& options,
                               std::string* peer_note) {
  std::vector<BenchRow> rows;
  // The first reason a peer did not run (the same for all, as a rule).
  std::string note;
  auto keep = [&](const std::string& n) {
    if (note.empty()) note = n;
  };
  if (Wanted(options, "thread")) keep(BenchThread(options, &rows));
  if (Wanted(options, "cloth")) keep(BenchCloth(options, &rows));
  if (Wanted(options, "slab")) keep(BenchSlab(options, &rows));
  if (Wanted(options, "holes")) keep(BenchHoles(options, &rows));
  if (Wanted(options, "lafortune")) keep(BenchLafortune(options, &rows));
  if (peer_note) *peer_note = note;
  return rows;
}

void WriteBenchCsv(const std::vector<BenchRow>& rows, const std::string& path) {
  std::ostringstream out;
  out << "model,config,default,repeats,wall_median_s,wall_min_s,wall_max_s,"
         "cpu_median_s,peak_mb,value_error,param_error,size,success\n";
  for (const BenchRow& r : rows) {
    out << r.model << ",\"" << r.config << "\"," << (r.is_default ? 1 : 0)
        << "," << r.repeats << "," << Number(r.wall_median_s) << ","
        << Number(r.wall_min_s) << "," << Number(r.wall_max_s) << ","
        << Number(r.cpu_median_s) << "," << Number(r.peak_mb) << ","
        << Number(r.value_error) << "," << Number(r.param_error) << ","
        << Number(r.size) << "," << (r.success ? 1 : 0) << "\n";
  }
  WriteFileAtomically(path, out.str());
}

double ToleranceChoice(const std::vector<BenchRow>& rows, double slack) {
  double best = std::numeric_limits<double>::infinity();
  for (const BenchRow& r : rows) {
    if (std::isfinite(r.size) && std::isfinite(r.value_error)) {
      best = std::min(best, r.value_error);
    }
  }
  double choice = kNaN;
  for (const BenchRow& r : rows) {
    if (std::isfinite(r.size) && r.value_error <= best * (1.0 + slack) &&
        !(r.size >= choice)) {
      choice = r.size;
    }
  }
  return choice;
}

std::vector<std::string> WriteBenchReport(const std::vector<BenchRow>& rows,
                                          const BenchOptions& options,
                                          const std::string& dir,
                                          const std::string& peer_note) {
  std::vector<std::string> files;
  std::vector<std::string> models;
  for (const BenchRow& r : rows) {
    if (std::find(models.begin(), models.end(), r.model) == models.end()) {
      models.push_back(r.model);
    }
  }
  constexpr double kSlack = 0.02;
  std::ostringstream md;
  md << "# clothfit bench" << (options.quick ? " (quick)" : "") << "\n\n"
     << "Each configuration ran " << std::max(1, options.repeats)
     << " time(s); wall time is the median with [min, max]. Errors are "
        "against truth held out from the fit; peak MB growth is the resident "
        "memory the runs added at their peak (docs/bench.md). The charts "
        "ring the default configuration.\n";
  for (const std::string& model : models) {
    std::vector<BenchRow> mine;
    for (const BenchRow& r : rows) {
      if (r.model == model) mine.push_back(r);
    }
    const ScatterChart speed = SpeedAccuracyChart(model, mine);
    const std::string speed_png = dir + "/" + model + "_speed_accuracy.png";
    WriteScatterChartPng(speed, speed_png);
    files.push_back(speed_png);

    md << "\n## " << model << "\n\n![speed against accuracy](" << model
       << "_speed_accuracy.png)\n";
    // The peer beside clothfit's same problem: the configuration its
    // config names after the solver ("scipy least_squares method=alg31
    // level=top"), else the default (Lafortune: the same lobe count K
    // without lookup table).
    const std::string kPeerName = "scipy least_squares";
    for (const BenchRow& peer : mine) {
      if (peer.group != "SciPy peer") continue;
      const size_t at = peer.config.find("lobes=");
      const std::string lobes =
          at == std::string::npos ? "" : peer.config.substr(at, 7);
      const std::string twin = peer.config.size() > kPeerName.size()
                                   ? peer.config.substr(kPeerName.size() + 1)
                                   : "";
      for (const BenchRow& r : mine) {
        if (r.group == "SciPy peer") continue;
        const bool same =
            !lobes.empty()
                ? r.config.rfind(lobes + " lut=off tolerance=1e-5 threads=all",
                                 0) == 0
            : twin.empty() ? r.is_default
                           : r.config == twin;
        if (!same) continue;
        md << "\nSciPy peer" << (lobes.empty() ? "" : ", " + lobes)
           << (!lobes.empty() ? " without lookup table"
               : twin.empty() ? " against clothfit's default"
                              : " against clothfit's " + twin)
           << ": " << Short(peer.cpu_median_s) << " s CPU against clothfit's "
           << Short(r.cpu_median_s) << " s ("
           << Short(peer.cpu_median_s / r.cpu_median_s)
           << " x); held-out error " << Short(peer.value_error) << " against "
           << Short(r.value_error) << " (difference "
           << Short(peer.value_error - r.value_error) << ").\n";
      }
    }
    const bool has_peer = model == "thread" || model == "cloth" ||
                          model == "slab" || model == "lafortune" ||
                          model == "holes";
    if (has_peer && !peer_note.empty()) md << "\n" << peer_note << ".\n";
    bool sized = false;
    for (const BenchRow& r : mine) sized = sized || std::isfinite(r.size);
    if (sized) {
      std::vector<std::string> groups;
      for (const BenchRow& r : mine) {
        if (std::isfinite(r.size) &&
            std::find(groups.begin(), groups.end(), r.group) == groups.end()) {
          groups.push_back(r.group);
        }
      }
      for (const std::string& group : groups) {
        std::vector<BenchRow> in_group;
        for (const BenchRow& r : mine) {
          if (std::isfinite(r.size) && r.group == group) in_group.push_back(r);
        }
        const double pick = ToleranceChoice(in_group, kSlack);
        md << "\n`--tolerance` just above the best error of " << group << " (+"
           << kSlack * 100 << " %) picks size " << Number(pick) << ".\n";
      }
      const std::string size_png = dir + "/" + model + "_size.png";
      WriteScatterChartPng(ErrorSizeChart(model, mine), size_png);
      files.push_back(size_png);
      md << "\n![error against model size](" << model << "_size.png)\n";
    }
    md << "\n| config | wall median [min, max] s | CPU s | peak MB growth | "
          "held-out error | parameter error | converged |\n"
          "|---|---|---|---|---|---|---|\n";
    for (const BenchRow& r : mine) {
      md << "| " << r.config << (r.is_default ? " **(default)**" : "") << " | "
         << Short(r.wall_median_s) << " [" << Short(r.wall_min_s) << ", "
         << Short(r.wall_max_s) << "] | " << Short(r.cpu_median_s) << " | "
         << Short(r.peak_mb) << " | " << Short(r.value_error) << " | "
         << Short(r.param_error) << " | " << (r.success ? "yes" : "no")
         << " |\n";
    }
  }
  const std::string summary = dir + "/summary.md";
  WriteFileAtomically(summary, md.str());
  files.push_back(summary);
  return files;
}

}  // namespace clothfit
