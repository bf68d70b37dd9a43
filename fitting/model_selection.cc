#include "fitting/model_selection.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <sstream>

namespace clothfit {
namespace {

int FreeCount(const FitReport& r) {
  int k = 0;
  for (const ParameterReport& p : r.parameters) k += p.free;
  return k;
}

double Bic(const FitReport& r, bool sigma_known) {
  const int k = FreeCount(r);
  const double n = std::max(1, r.residuals);
  if (sigma_known) return 2.0 * r.final_cost + k * std::log(n);
  return BicOfRss(2.0 * r.final_cost, n, k);
}

}  // namespace

double BicOfRss(double rss, double n, int k) {
  return n * std::log(std::max(rss, 1e-300) / n) + k * std::log(n);
}

namespace {

CandidateReport Describe(const std::string& description, int samples,
                         const FitReport& r, bool sigma_known,
                         double tolerance) {
  CandidateReport c;
  c.description = description;
  c.free_parameters = FreeCount(r);
  c.samples = samples;
  c.usable = r.usable;
  c.relative_rms = r.relative_rms;
  c.bic = Bic(r, sigma_known);
  c.meets_tolerance = r.usable && r.relative_rms <= tolerance;
  return c;
}

struct ClothCandidate {
  std::string description;
  ClothParams init;
  std::vector<std::string> extra_fix;
  bool shared_albedo = false;
  int free_estimate = 0;
  int samples = 0;
};

int TotalSamples(const ClothParams& c) {
  int t = 0;
  for (const ClothThread& th : c.threads) {
    t += static_cast<int>(th.offsets_deg.size());
  }
  return t;
}

// The first candidate that meets the tolerance; else the usable one with
// the lowest BIC; else the last. Sets the report's reason.
int Choose(SelectionReport* report) {
  const std::vector<CandidateReport>& c = report->candidates;
  for (size_t i = 0; i < c.size(); ++i) {
    if (c[i].meets_tolerance) {
      report->reason = "the simplest candidate that meets the tolerance";
      return static_cast<int>(i);
    }
  }
  int chosen = -1;
  for (size_t i = 0; i < c.size(); ++i) {
    if (c[i].usable && (chosen < 0 || c[i].bic < c[chosen].bic)) {
      chosen = static_cast<int>(i);
    }
  }
  report->reason =
      "no candidate meets the tolerance; the usable one with the lowest BIC";
  if (chosen < 0) {
    report->reason = "no candidate reached a usable solution";
    chosen = static_cast<int>(c.size()) - 1;
  }
  return chosen;
}

}  // namespace

std::string SelectionReportText(const SelectionReport& r) {
  std::ostringstream out;
  bool heldout = false;
  for (const CandidateReport& c : r.candidates) {
    heldout = heldout || c.heldout_relative_rms >= 0.0;
  }
  if (heldout) {
    out << "model selection (held-out error)\n";
  } else {
    out << "model selection (tolerance: relative rms <= " << r.tolerance
        << ")\n";
  }
  bool timed = false;
  for (const CandidateReport& c : r.candidates) timed = timed || c.seconds >= 0;
  char line[320];
  std::snprintf(line, sizeof(line), "  %-50s %6s %8s %12s %12s%s%s\n",
                "candidate", "free", "samples", "rel. rms", "BIC",
                heldout ? "     held-out" : "", timed ? "        s" : "");
  out << line;
  for (size_t i = 0; i < r.candidates.size(); ++i) {
    const CandidateReport& c = r.candidates[i];
    char held[32] = "";
    if (heldout) {
      std::snprintf(held, sizeof(held), " %12.4g", c.heldout_relative_rms);
    }
    char secs[32] = "";
    if (timed) std::snprintf(secs, sizeof(secs), " %8.2f", c.seconds);
    const std::string samples =
        c.samples < 0 ? std::string("-") : std::to_string(c.samples);
    std::snprintf(line, sizeof(line), "%s %-50s %6d %8s %12.4g %12.6g%s%s%s\n",
                  static_cast<int>(i) == r.chosen ? "*" : " ",
                  c.description.c_str(), c.free_parameters, samples.c_str(),
                  c.relative_rms, c.bic, held, secs,
                  !c.usable               ? "  (failed)"
                  : c.meets_tolerance     ? "  meets"
                  : timed && !c.converged ? "  (not converged)"
                                          : "");
    out << line;
    if (!c.note.empty()) out << "    (" << c.note << ")\n";
  }
  out << "chosen: " << r.reason << "\n";
  return out.str();
}

std::string SelectionReportJson(const SelectionReport& r) {
  nlohmann::ordered_json j;
  j["tolerance"] = r.tolerance;
  j["chosen"] = r.chosen >= 0 ? r.candidates[r.chosen].description : "";
  j["reason"] = r.reason;
  nlohmann::ordered_json list = nlohmann::ordered_json::array();
  for (const CandidateReport& c : r.candidates) {
    nlohmann::ordered_json e;
    e["description"] = c.description;
    e["free_parameters"] = c.free_parameters;
    if (c.samples >= 0) e["samples"] = c.samples;
    e["relative_rms"] = c.relative_rms;
    e["bic"] = c.bic;
    if (c.heldout_relative_rms >= 0.0) {
      e["heldout_relative_rms"] = c.heldout_relative_rms;
    }
    e["usable"] = c.usable;
    e["meets_tolerance"] = c.meets_tolerance;
    if (c.seconds >= 0.0) {
      e["seconds"] = c.seconds;
      e["converged"] = c.converged;
    }
    if (!c.note.empty()) e["note"] = c.note;
    list.push_back(e);
  }
  j["candidates"] = list;
  return j.dump();
}

ClothParams ResampleTangentCurves(const ClothParams& c, int t, bool* changed) {
  ClothParams out = c;
  if (changed) *changed = false;
  for (ClothThread& th : out.threads) {
    if (th.curve.lengths.empty() ||
        static_cast<int>(th.offsets_deg.size()) <= t) {
      continue;
    }
    th.curve.samples = t;
    if (!ValidateTangentCurve(th.curve).empty()) continue;
    th.offsets_deg = SampleTangentCurve(th.curve);
    if (changed) *changed = true;
  }
  return out;
}

ClothSelection SelectClothModel(const MeasurementTable& table,
                                const ClothParams& init,
                                const ClothFitOptions& options,
                                double tolerance) {
  // Tangent-sample variants: T = 1, 2, 4, ... below each curve's count.
  int max_samples = 0;
  for (const ClothThread& th : init.threads) {
    max_samples =
        std::max(max_samples, static_cast<int>(th.offsets_deg.size()));
  }
  std::vector<std::pair<std::string, ClothParams>> weaves;
  for (int t = 1; t < max_samples; t *= 2) {
    bool changed = false;
    const ClothParams c = ResampleTangentCurves(init, t, &changed);
    if (changed) weaves.emplace_back("T=" + std::to_string(t), c);
  }
  weaves.emplace_back("T as given", init);

  const bool many = init.threads.size() > 1;
  std::vector<ClothCandidate> candidates;
  for (const auto& [weave_name, weave] : weaves) {
    for (int kd_mode = 0; kd_mode < 3; ++kd_mode) {  // 0, 1, free
      for (int shared = many ? 1 : 0; shared >= 0; --shared) {
        ClothCandidate c;
        c.init = weave;
        c.samples = TotalSamples(weave);
        c.shared_albedo = shared;
        c.description = weave_name;
        if (kd_mode < 2) {
          for (ClothThread& th : c.init.threads) th.params.kd = kd_mode;
          c.extra_fix.push_back("kd");
          c.description += kd_mode == 0 ? ", kd=0" : ", kd=1";
        } else {
          c.description += ", kd free";
        }
        if (shared) c.description += ", shared albedo";
        // Free parameters with the default free set: per thread gamma_s,
        // gamma_v (+ kd), and 3 albedos per thread or 3 in all.
        const int n = static_cast<int>(init.threads.size());
        c.free_estimate = n * (2 + (kd_mode == 2)) + (shared ? 3 : 3 * n);
        candidates.push_back(c);
      }
    }
  }
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const ClothCandidate& a, const ClothCandidate& b) {
                     if (a.free_estimate != b.free_estimate) {
                       return a.free_estimate < b.free_estimate;
                     }
                     return a.samples < b.samples;
                   });

  ClothSelection out;
  out.report.tolerance = tolerance;
  std::vector<std::pair<ClothFitResult, ClothParams>> fits;
  for (size_t i = 0; i < candidates.size(); ++i) {
    const ClothCandidate& c = candidates[i];
    if (options.solver.progress) {
      options.solver.progress("candidate " + std::to_string(i + 1) + " of " +
                              std::to_string(candidates.size()) + ": " +
                              c.description);
    }
    ClothFitOptions o = options;
    o.shared_albedo = c.shared_albedo;
    o.fix.insert(o.fix.end(), c.extra_fix.begin(), c.extra_fix.end());
    ClothFitResult fit = FitCloth(table, c.init, o);
    out.report.candidates.push_back(
        Describe(c.description, c.samples, fit.report,
                 !fit.report.noise_level_estimated, tolerance));
    fits.emplace_back(std::move(fit), c.init);
    if (out.report.candidates.back().meets_tolerance) break;
  }
  const int chosen = Choose(&out.report);
  out.report.chosen = chosen;
  out.fit = fits[chosen].first;
  out.params = fits[chosen].second;
  return out;
}

ThreadSelection SelectThreadModel(const MeasurementTable& table,
                                  const ThreadFitOptions& options,
                                  double tolerance) {
  ThreadSelection out;
  out.report.tolerance = tolerance;
  std::vector<ThreadFitResult> fits;
  const char* names[] = {"kd=0", "kd=1", "kd free"};
  for (int kd_mode = 0; kd_mode < 3; ++kd_mode) {
    ThreadFitOptions o = options;
    if (kd_mode < 2) {
      o.fix.push_back("kd");
      if (!o.init) o.init = ThreadParams();
      o.init->kd = kd_mode;
    }
    fits.push_back(FitThread(table, o));
    out.report.candidates.push_back(
        Describe(names[kd_mode], 0, fits.back().report,
                 !fits.back().report.noise_level_estimated, tolerance));
    if (out.report.candidates.back().meets_tolerance) break;
  }
  out.report.chosen = Choose(&out.report);
  out.fit = fits[out.report.chosen];
  return out;
}

}  // namespace clothfit
