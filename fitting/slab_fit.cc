#include "fitting/slab_fit.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "fitting/least_squares.h"
#include "fitting/model_residual_internal.h"
#include "io/input_error.h"
#include "models/evaluate.h"

namespace clothfit {
namespace {

// One row of one table (fitting/model_residual_internal.h). A one-channel
// table has one residual per row (channel 0); in an rgb fit that is a
// direct-transmittance table, whose value is that of every channel when
// they share tau.
using Sample = FitRow;

// The squared residual factors (fitting/residual_weight.h) of the channels
// that have a residual, 0 for the others.
glm::dvec3 Weight2(const Sample& s) {
  const glm::dvec3& scale = s.scale;
  return s.channels == 1 ? glm::dvec3(scale.x * scale.x, 0.0, 0.0)
                         : scale * scale;
}

// The slab's value at sample i; with a shared tau, entry 0 of the block is
// the tau of every channel.
struct SlabEvaluator {
  FitRows samples;
  bool shared_tau;

  template <typename T>
  Vec3<T> operator()(const T* const* blocks, size_t i) const {
    SlabParamsT<T> p;
    FromArray(blocks[0], &p);
    if (shared_tau) p.tau = Vec3<T>(blocks[0][0]);
    const Sample s = samples[i];
    return Value(p, s.row->wi, s.row->wo, s.quantity);
  }
};

// The parameters of the flat vector x (ToArray layout) as fitted.
SlabParams FromX(const std::vector<double>& x, bool shared_tau,
                 bool one_channel) {
  SlabParams p;
  FromArray(x.data(), &p);
  if (shared_tau) p.tau = glm::dvec3(p.tau.x);
  if (one_channel) p.albedo = glm::dvec3(p.albedo.x);
  return p;
}

FitRows Samples(const std::vector<MeasurementTable>& tables,
                const std::vector<Weighting>& weightings) {
  FitRows samples;
  for (size_t t = 0; t < tables.size(); ++t) {
    samples.Append(tables[t], weightings[t]);
  }
  return samples;
}

// Starting points: a log grid over tau (with the initial value) and, for
// each tau, the albedo per channel in closed form (the model is linear in
// it; direct-transmittance rows do not depend on it).
std::vector<std::vector<double>> Starts(const FitRows& samples,
                                        const std::vector<ParameterSpec>& specs,
                                        const SlabParams& init, int channels,
                                        bool shared_tau, int keep) {
  std::vector<double> taus = {init.tau.x};
  if (specs[0].free || specs[1].free || specs[2].free) {
    for (double tau = 1e-3; tau < 31.0; tau *= std::pow(10.0, 1.0 / 6.0)) {
      taus.push_back(tau);
    }
  }
  // cost[g][c] and albedo[g][c] at grid point g for channel c.
  std::vector<glm::dvec3> cost(taus.size()), albedo(taus.size());
  for (size_t g = 0; g < taus.size(); ++g) {
    SlabParams unit;
    unit.tau = glm::dvec3(taus[g]);
    unit.albedo = glm::dvec3(1.0);
    glm::dvec3 sgg(0.0), sgv(0.0), svv(0.0), direct(0.0);
    for (const Sample& s : samples) {
      const glm::dvec3 m = Value(unit, s.row->wi, s.row->wo, s.quantity);
      const glm::dvec3 s2 = Weight2(s);
      if (s.quantity == Quantity::kTransmittance) {
        direct += s2 * (m - s.row->value) * (m - s.row->value);
      } else {
        sgg += s2 * m * m;
        sgv += s2 * m * s.row->value;
        svv += s2 * s.row->value * s.row->value;
      }
    }
    for (int c = 0; c < 3; ++c) {
      double a = init.albedo[c];
      if (specs[3 + c].free && sgg[c] > 0.0) {
        a = std::clamp(sgv[c] / sgg[c], 0.0, 1.0);
      }
      albedo[g][c] = a;
      cost[g][c] = svv[c] - 2.0 * a * sgv[c] + a * a * sgg[c] + direct[c];
    }
  }
  // Per channel (or for all, with a shared tau): grid points by cost, and
  // the best `keep` that lie a factor 2 apart.
  auto best = [&](int c) {
    std::vector<size_t> order(taus.size());
    for (size_t g = 0; g < order.size(); ++g) order[g] = g;
    auto total = [&](size_t g) {
      if (c >= 0) return cost[g][c];
      double sum = 0.0;
      for (int k = 0; k < channels; ++k) sum += cost[g][k];
      return sum;
    };
    std::sort(order.begin(), order.end(),
              [&](size_t a, size_t b) { return total(a) < total(b); });
    std::vector<size_t> picked;
    for (size_t g : order) {
      bool distinct = true;
      for (size_t p : picked) {
        distinct =
            distinct && std::abs(std::log(taus[g] / taus[p])) >= std::log(2.0);
      }
      if (distinct) picked.push_back(g);
      if (static_cast<int>(picked.size()) == keep) break;
    }
    return picked;
  };
  std::vector<std::vector<size_t>> picks;
  for (int c = 0; c < 3; ++c) {
    picks.push_back(best(shared_tau || c >= channels ? -1 : c));
  }
  std::vector<std::vector<double>> starts;
  for (size_t k = 0; k < picks[0].size(); ++k) {
    SlabParams p = init;
    for (int c = 0; c < 3; ++c) {
      const size_t g = picks[c][std::min(k, picks[c].size() - 1)];
      if (specs[c].free) p.tau[c] = taus[g];
      p.albedo[c] = albedo[g][c];
    }
    std::vector<double> x(FlatSize(p));
    ToArray(p, x.data());
    starts.push_back(x);
  }
  return starts;
}

// The constant-alpha baseline (the paper's comparison), in closed form per
// channel: a Lambertian f = k (rho = k mu_i for cosine-weighted tables) and
// a constant direct transmittance 1 - alpha. Back-lit rows either get the
// same k (rendered as if front-lit) or 0 (black).
struct Baseline {
  std::string variant;
  double cost = 0.0;  // sum of squared normalised residuals
  double se = 0.0;    // sum of squared residuals, data units
  int parameters = 0;
};

Baseline FitBaseline(const FitRows& samples, int channels,
                     bool back_lit_black) {
  glm::dvec3 skk(0.0), skv(0.0), sd(0.0), sdv(0.0);
  bool any_bsdf = false, any_direct = false;
  for (const Sample& s : samples) {
    const glm::dvec3 s2 = Weight2(s);
    if (s.quantity == Quantity::kTransmittance) {
      sd += s2;
      sdv += s2 * s.row->value;
      any_direct = true;
      continue;
    }
    any_bsdf = true;
    if (back_lit_black && SlabTransmits(s.row->wi, s.row->wo)) continue;
    const double k = QuantityFactor(Quantity::kBrdf, s.quantity, s.row->wi.z);
    skk += s2 * k * k;
    skv += s2 * k * s.row->value;
  }
  glm::dvec3 lambert(0.0), transmit(0.0);
  for (int c = 0; c < 3; ++c) {
    if (skk[c] > 0.0) lambert[c] = std::max(0.0, skv[c] / skk[c]);
    if (sd[c] > 0.0) transmit[c] = std::clamp(sdv[c] / sd[c], 0.0, 1.0);
  }
  Baseline b;
  b.variant = back_lit_black ? "Lambertian BRDF, back-lit black"
                             : "Lambertian BRDF, back-lit as front-lit";
  b.parameters = channels * ((any_bsdf ? 1 : 0) + (any_direct ? 1 : 0));
  for (const Sample& s : samples) {
    glm::dvec3 m = transmit;
    if (s.quantity != Quantity::kTransmittance) {
      const bool black = back_lit_black && SlabTransmits(s.row->wi, s.row->wo);
      m = black ? glm::dvec3(0.0)
                : lambert *
                      QuantityFactor(Quantity::kBrdf, s.quantity, s.row->wi.z);
    }
    for (int c = 0; c < s.channels; ++c) {
      const double r = m[c] - s.row->value[c];
      b.se += r * r;
      b.cost += r * r * Weight2(s)[c];
    }
  }
  return b;
}

std::string Format(const char* format, double a, double b = 0.0) {
  char text[256];
  std::snprintf(text, sizeof(text), format, a, b);
  return text;
}

SlabValidity Validate(const FitRows& samples, int channels, bool sigma_known,
                      const SlabParams& p, const FitReport& report) {
  SlabValidity v;
  v.sigma_known = sigma_known;
  double cost = 0.0, se = 0.0, ss = 0.0;
  int entries = 0;
  for (const Sample& s : samples) {
    const glm::dvec3 m = Value(p, s.row->wi, s.row->wo, s.quantity);
    const glm::dvec3 w2 = Weight2(s);
    for (int c = 0; c < s.channels; ++c) {
      const double r = m[c] - s.row->value[c];
      se += r * r;
      ss += s.row->value[c] * s.row->value[c];
      cost += r * r * w2[c];
      ++entries;
    }
  }
  int free_parameters = 0;
  for (const ParameterReport& q : report.parameters) {
    free_parameters += q.free ? 1 : 0;
  }
  v.dof = std::max(1, entries - free_parameters);
  v.slab_rms = std::sqrt(se / std::max(1, entries));
  v.max_tau = std::max({p.tau.x, p.tau.y, p.tau.z});
  if (sigma_known) {
    v.chi2_per_dof = cost / v.dof;
    v.chi2_limit = 1.0 + 3.0 * std::sqrt(2.0 / v.dof);
    v.error_exceeds_noise = v.chi2_per_dof > v.chi2_limit;
    v.notes.push_back(
        v.error_exceeds_noise
            ? Format("The model's error exceeds the data's noise: chi2/dof = "
                     "%.4g > %.4g (3-sigma limit for noise alone).",
                     v.chi2_per_dof, v.chi2_limit)
            : Format("The model explains the data to within their noise: "
                     "chi2/dof = %.4g <= %.4g.",
                     v.chi2_per_dof, v.chi2_limit));
  } else {
    v.notes.push_back(Format(
        "The noise level is not known (it is estimated from the residuals, "
        "level %.3g), so the model's error cannot be compared with the "
        "noise (relative rms error %.4g).",
        report.noise_level, ss > 0.0 ? std::sqrt(se / ss) : 0.0));
  }
  v.above_paper_tau_limit = v.max_tau > kSlabPaperTauLimit;
  v.estimated_model_error = SlabParamsSingleScatterError(p);
  for (int c = 0; c < 3; ++c) {
    v.corrected_albedo[c] = SlabMultipleScatteringAlbedo(p.tau[c], p.albedo[c]);
  }
  v.multiple_scattering = v.estimated_model_error > kSlabRegimeTolerance;
  std::string regime =
      Format(
          "Estimated error of single scattering against all orders: "
          "A q(tau) = %.2g %%",
          100.0 * v.estimated_model_error) +
      Format(" (tau = %.4g", v.max_tau) +
      (v.above_paper_tau_limit ? ", above the paper's bound 0.2)." : ").");
  if (v.multiple_scattering) {
    regime += Format(
        " Multiple scattering is not negligible (> %.0f %%): the fitted "
        "albedo absorbs it; corrected for it: %.4g",
        100.0 * kSlabRegimeTolerance, v.corrected_albedo.x);
    if (channels == 3) {
      regime += Format(", %.4g", v.corrected_albedo.y) +
                Format(", %.4g", v.corrected_albedo.z);
    }
    regime += " (docs/slab.md).";
  } else {
    regime += " Within the single-scattering regime.";
  }
  v.notes.push_back(regime);
  const Baseline front = FitBaseline(samples, channels, false);
  const Baseline black = FitBaseline(samples, channels, true);
  const Baseline& b = black.cost < front.cost ? black : front;
  v.baseline = b.variant;
  v.baseline_rms = std::sqrt(b.se / std::max(1, entries));
  if (sigma_known) {
    v.baseline_chi2_per_dof = b.cost / std::max(1, entries - b.parameters);
  }
  // Normalised residuals (by sigma and weight), so that tables in other
  // units (f and D) count by their precision.
  v.improvement = cost > 0.0 ? std::sqrt(b.cost / cost) : HUGE_VAL;
  // In words that hold whichever is better (a ratio below 1 is "higher").
  const std::string comparison =
      cost > 0.0 && b.cost > 0.0
          ? (v.improvement >= 1.0
                 ? Format("the slab model's weighted rms error is %.3gx lower.",
                          v.improvement)
                 : Format("the slab model's weighted rms error is %.3gx "
                          "higher.",
                          1.0 / v.improvement))
          : (cost > 0.0 ? std::string("the baseline fits exactly.")
                        : std::string("the slab model fits exactly."));
  v.notes.push_back("Constant-alpha baseline (" + b.variant +
                    Format("): rms error %.4g against %.4g for the slab "
                           "model; ",
                           v.baseline_rms, v.slab_rms) +
                    comparison);
  v.within_regime = !v.multiple_scattering && !v.error_exceeds_noise;
  return v;
}

}  // namespace

SlabFitResult FitSlab(const std::vector<MeasurementTable>& tables,
                      const SlabFitOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();  // search + solves
  if (tables.empty()) throw InputError("slab fit: no tables");
  // The BSDF tables decide the channels (transmittance tables alone else).
  int channels = 0;
  for (const MeasurementTable& table : tables) {
    if (table.quantity != Quantity::kTransmittance) channels = table.channels;
  }
  if (channels == 0) channels = tables.front().channels;
  // One noise model for all tables, each weighted by its own values
  // (fitting/residual_weight.h); an unknown level is one for all.
  std::vector<Weighting> weightings;
  for (const MeasurementTable& table : tables) {
    weightings.emplace_back(table, options.solver.noise);
  }
  const bool sigma_known = weightings.front().LevelKnown();
  for (size_t t = 0; t < tables.size(); ++t) {
    const MeasurementTable& table = tables[t];
    if (table.rows.empty()) throw InputError("slab fit: a table has no rows");
    RequireWeightedRows(table);
    const bool one_channel_direct =
        table.quantity == Quantity::kTransmittance && table.channels == 1 &&
        !options.per_channel_tau;
    if (table.channels != channels && !one_channel_direct) {
      throw InputError(
          "slab fit: tables mix one-channel ('value') and rgb values (a "
          "one-channel transmittance table goes with rgb tables only when "
          "tau is shared)");
    }
    if (weightings[t].kind() != weightings.front().kind()) {
      throw InputError(
          "slab fit: some tables give sigma and others do not; residuals "
          "would mix normalised and raw units (give all tables sigma, or "
          "choose a noise model)");
    }
  }
  const bool one_channel = channels == 1;
  const bool shared_tau = !options.per_channel_tau || one_channel;
  const SlabParams init = options.init ? *options.init : SlabParams();
  if (!options.per_channel_tau && !SlabTauIsScalar(init)) {
    throw InputError(
        "slab fit: the initial parameters have one tau per channel; fit "
        "them with a per-channel tau");
  }

  LeastSquaresProblem lsq;
  lsq.specs = ParameterSpecs(SlabParams());
  if (shared_tau) lsq.specs[0].name = "tau";
  if (one_channel) lsq.specs[3].name = "albedo";
  ApplyFreeFix(options.fix, options.free_only, &lsq.specs);
  for (int c = 1; c < 3; ++c) {  // channels that follow the first
    if (shared_tau) lsq.specs[c].free = false;
    if (one_channel) lsq.specs[3 + c].free = false;
  }
  lsq.block_sizes = {FlatSize(SlabParams())};
  lsq.sigma_known = sigma_known;
  const FitRows samples = Samples(tables, weightings);
  ResidualBlocks blocks;
  blocks.used = {0};
  SetModelResiduals(
      std::make_shared<const SlabEvaluator>(SlabEvaluator{samples, shared_tau}),
      samples, blocks, &lsq);

  const std::vector<std::vector<double>> starts =
      Starts(samples, lsq.specs, init, channels, shared_tau,
             std::max(1, options.solve_starts));
  SlabFitResult result;
  std::vector<double> x = starts.front();
  result.report = SolveLeastSquares(lsq, starts, options.solver, &x);
  ReportWeighting(weightings.front(), &result.report);
  result.params = FromX(x, shared_tau, one_channel);
  for (const MeasurementTable& table : tables) {
    result.report.rows += static_cast<int>(table.rows.size());
  }
  // Entries that only follow the first channel are not parameters.
  std::vector<ParameterReport>& reported = result.report.parameters;
  reported.erase(
      std::remove_if(reported.begin(), reported.end(),
                     [&](const ParameterReport& p) {
                       return (shared_tau &&
                               (p.name == "tau_g" || p.name == "tau_b")) ||
                              (one_channel &&
                               (p.name == "albedo_g" || p.name == "albedo_b"));
                     }),
      reported.end());
  if (result.report.usable) {
    result.validity =
        Validate(samples, channels, sigma_known, result.params, result.report);
  }
  result.report.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0)
          .count();
  return result;
}

std::vector<double> SlabValuesInReportOrder(const SlabParams& p,
                                            const FitReport& report) {
  std::vector<double> values;
  for (const ParameterReport& q : report.parameters) {
    const bool tau = q.name.rfind("tau", 0) == 0;
    const glm::dvec3& v = tau ? p.tau : p.albedo;
    const char last = q.name.back();
    values.push_back(last == 'g' ? v.y : last == 'b' ? v.z : v.x);
  }
  return values;
}

std::string SlabValidityJson(const SlabValidity& v) {
  nlohmann::ordered_json j;
  j["within_regime"] = v.within_regime;
  if (v.sigma_known) {
    j["chi2_per_dof"] = v.chi2_per_dof;
    j["chi2_limit"] = v.chi2_limit;
    j["error_exceeds_noise"] = v.error_exceeds_noise;
  }
  j["dof"] = v.dof;
  j["max_tau"] = v.max_tau;
  j["above_paper_tau_limit"] = v.above_paper_tau_limit;
  j["estimated_model_error"] = v.estimated_model_error;
  j["multiple_scattering"] = v.multiple_scattering;
  j["corrected_albedo"] = {v.corrected_albedo.x, v.corrected_albedo.y,
                           v.corrected_albedo.z};
  j["slab_rms"] = v.slab_rms;
  nlohmann::ordered_json baseline;
  baseline["variant"] = v.baseline;
  baseline["rms"] = v.baseline_rms;
  if (v.sigma_known) baseline["chi2_per_dof"] = v.baseline_chi2_per_dof;
  j["constant_alpha_baseline"] = baseline;
  j["improvement"] = v.improvement;
  j["notes"] = v.notes;
  return j.dump();
}

std::string SlabValidityText(const SlabValidity& v) {
  std::string out = v.within_regime
                        ? "validity: the data are within the model's regime\n"
                        : "validity: the data are OUTSIDE the model's regime\n";
  for (const std::string& note : v.notes) out += "  " + note + "\n";
  return out;
}

}  // namespace clothfit
