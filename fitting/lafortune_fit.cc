#include "fitting/lafortune_fit.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <sstream>
#include <unordered_map>

#include "fitting/ceres_linear_solver_internal.h"
#include "fitting/energy.h"
#include "fitting/lafortune_bounds_internal.h"
#include "fitting/lafortune_joint_internal.h"
#include "fitting/lafortune_lobes_internal.h"
#include "fitting/residual_weight.h"
#include "io/input_error.h"
#include "models/evaluate.h"

namespace clothfit {
namespace {

// The fits' bound on T: a non-negative factor, at most 1e3.
constexpr double kMaxT = 1e3;

// Iteration cap of the lobe fits after the first pass (warm starts).
constexpr int kLaterPassIterations = 8;

// The lobes of the paper's start (Section 5): grey diffuse, moderate
// highlight, slightly anisotropic lobes (Cx = 1.22 Cy for the first,
// Cy = 1.22 Cx for the second lobe).
LafortuneParams PaperStart(int lobes, double diffuse, double c) {
  LafortuneParams p;
  p.diffuse = glm::dvec3(diffuse);
  for (int k = 0; k < lobes; ++k) {
    LafortuneLobe lobe;
    const double ax = k % 2 == 0 ? 1.22 : 1.0, ay = k % 2 == 0 ? 1.0 : 1.22;
    lobe.cx = glm::dvec3(-c * ax);
    lobe.cy = glm::dvec3(-c * ay);
    lobe.cz = glm::dvec3(c);
    lobe.n = glm::dvec3(10.0);
    p.lobes.push_back(lobe);
  }
  return p;
}

double Cost(const TexelSamples& s, const std::vector<glm::dvec3>& t,
            const LafortuneParams& p) {
  double cost = 0.0;
  for (size_t i = 0; i < s.size(); ++i) {
    const glm::dvec3 m = t[s.view[i]] * LafortuneF1(p, s.l[i], s.v[i]);
    const glm::dvec3 d = m - s.value[i];
    cost += glm::dot(s.weight[i] * d, d);
  }
  return std::isfinite(cost) ? cost : HUGE_VAL;
}

bool Finite(const LafortuneParams& p) {
  bool ok = std::isfinite(glm::dot(p.diffuse, glm::dvec3(1.0)));
  for (const LafortuneLobe& l : p.lobes) {
    ok = ok && std::isfinite(glm::dot(l.cx + l.cy + l.cz + l.n, glm::dvec3(1)));
  }
  return ok;
}

}  // namespace

std::vector<bool> LafortuneOwnedViews(const TexelSamples& samples,
                                      int min_lut_samples) {
  std::vector<int> view_samples(samples.views.size(), 0);
  for (size_t i = 0; i < samples.size(); ++i) ++view_samples[samples.view[i]];
  std::vector<bool> own(samples.views.size(), false);
  for (size_t k = 0; k < own.size(); ++k) {
    own[k] = view_samples[k] >= std::max(1, min_lut_samples);
  }
  return own;
}

LafortuneFitResult FitLafortuneOnce(const TexelSamples& samples,
                                    const LafortuneFitOptions& options) {
  LafortuneFitResult out;
  out.report.residuals = static_cast<int>(3 * samples.size());
  for (int rows : samples.count_rows) out.report.rows += rows;
  const int lobes = std::clamp(options.lobes, 0, 3);
  const size_t n_views = samples.views.size();
  std::vector<glm::dvec3> t(n_views, glm::dvec3(1.0));
  out.params.lut.views = samples.views;
  out.params.lut.alpha = samples.view_alpha;
  out.params.normal = samples.normal;
  if (samples.size() == 0) {
    out.params.params = PaperStart(lobes, 0.0, 1.0);
    out.params.lut.color = t;
    out.report.message = "no samples";
    return out;
  }
  // Starts: the paper's, and one scaled to the data: rho_d from the
  // weighted least squares of f1 = l.z rho_d, lobes sized so that their peak
  // c^N matches the brightest excess over it.
  glm::dvec3 num(0.0), den(0.0), peak(0.0);
  for (size_t i = 0; i < samples.size(); ++i) {
    const double lz = Foreshortening(samples.l[i]);
    num += samples.weight[i] * samples.value[i] * lz;
    den += samples.weight[i] * lz * lz;
  }
  const glm::dvec3 rho_d = glm::dvec3(den.x > 0 ? num.x / den.x : 0.0,
                                      den.y > 0 ? num.y / den.y : 0.0,
                                      den.z > 0 ? num.z / den.z : 0.0);
  // The lobes' peak: the largest excess of rho / l.z over rho_d, with l.z
  // floored at 1e-3 so that grazing samples do not decide the estimate.
  for (size_t i = 0; i < samples.size(); ++i) {
    const glm::dvec3 excess =
        samples.value[i] / std::max(samples.l[i].z, 1e-3) - rho_d;
    peak = glm::max(peak, excess);
  }
  // The views with enough samples for an entry of their own; the others
  // follow them by the table's interpolation.
  const std::vector<bool> own =
      LafortuneOwnedViews(samples, options.min_lut_samples);
  const int owned = static_cast<int>(std::count(own.begin(), own.end(), true));
  // Without a view to fit, or without signal, the table is T = 1: the fit
  // without one.
  bool signal = false;
  for (const glm::dvec3& y : samples.value) {
    signal = signal || y.x != 0.0 || y.y != 0.0 || y.z != 0.0;
  }
  const bool lut = options.lookup_table && owned > 0 && signal;
  if (!signal) {  // all values 0: exactly the zero model (C = 0, T = 1)
    out.params.params = PaperStart(lobes, 0.0, 0.0);
    out.params.lut.color = t;
    out.report.usable = out.report.converged = true;
    out.report.termination = "all values are 0: the zero model";
    out.report.lut_views = static_cast<int>(n_views);
    return out;
  }
  // A warm start (the best of a group's children), else the paper's.
  const LafortuneModel* warm = nullptr;
  double warm_cost = HUGE_VAL;
  for (const LafortuneModel* m : options.warm_starts) {
    if (m == nullptr || static_cast<int>(m->params.lobes.size()) != lobes ||
        m->lut.color.size() != n_views) {
      continue;
    }
    const double cost = Cost(samples, lut ? m->lut.color : t, m->params);
    if (cost < warm_cost) {
      warm_cost = cost;
      warm = m;
    }
  }
  if (warm != nullptr && lut) t = warm->lut.color;
  // A given start (--init) with this lobe count, and its lookup table when
  // it was fitted on the same views.
  const LafortuneModel* given =
      warm == nullptr && options.start != nullptr &&
              static_cast<int>(options.start->params.lobes.size()) == lobes
          ? options.start
          : nullptr;
  if (given != nullptr && lut && given->lut.views.size() == n_views &&
      given->lut.color.size() == n_views) {
    bool same_views = true;
    for (size_t k = 0; k < n_views && same_views; ++k) {
      same_views = glm::length(given->lut.views[k] - samples.views[k]) <= 1e-9;
    }
    if (same_views) t = given->lut.color;
  }
  std::vector<LafortuneParams> starts = {warm != nullptr ? warm->params
                                         : given != nullptr
                                             ? given->params
                                             : PaperStart(lobes, 0.5, 1.0)};
  if (options.data_driven_start && warm == nullptr) {
    const double mean_peak = std::max((peak.x + peak.y + peak.z) / 3.0, 1e-6);
    LafortuneParams d = PaperStart(lobes, 0.0, std::pow(mean_peak, 0.1));
    d.diffuse = glm::max(0.7 * rho_d, glm::dvec3(0.0));
    starts.push_back(d);
  }
  const double peak_cap =
      LafortunePeakCap(samples.largest_row_value, samples.value);
  LafortuneParams best;
  double best_cost = HUGE_VAL;
  // The first pass (from a start far from the solution, most of the
  // iterations) runs on a subsample; the later passes refine on all samples.
  const TexelSamples sub = Subsample(samples, options.first_pass_subsample);
  const TexelSamples& first = sub.size() > 0 ? sub : samples;
  // The joint solve (variable projection, fitting/lafortune_joint.cc)
  // starts from the first pass's lobes with T as started: from there it
  // reaches the optimum of representable data in 4x fewer iterations
  // than as its own first pass from the paper's start, and fewer texels
  // need the alternation (docs/lafortune.md).
  const bool joint = JointSolveRuns(options, lut);
  for (LafortuneParams p : starts) {
    out.report.iterations +=
        FitLobes(first, t, options, /*first_pass=*/true, peak_cap, &p);
    const double cost = Cost(samples, t, p);
    if (Finite(p) && cost < best_cost) {
      best_cost = cost;
      best = p;
    }
  }
  if (!(best_cost < HUGE_VAL)) {
    out.params.params = starts.front();
    out.params.lut.color = t;
    out.report.message = "the lobe fit produced no finite solution";
    return out;
  }
  out.report.alternations = 1;
  // Alternation: T in closed form per view and channel (eq. 4), then the
  // lobes again, until the mean relative change of T is small.
  bool lut_converged = false;
  // With the table off there are no views to speak of (the summary then
  // says nothing of a table).
  out.report.lut_views = options.lookup_table ? static_cast<int>(n_views) : 0;
  out.report.lut_views_fitted = lut ? owned : 0;
  if (joint) {
    // From the first pass's solution on all samples (a few iterations).
    const std::vector<glm::dvec3> before = t;
    const JointChannelResult r =
        SolveJoint(samples, own, options, kMaxT, peak_cap, &best, &t);
    out.report.iterations += r.iterations;
    if (r.usable) NormaliseLookupTable(own, peak_cap, &best, &t);
    double change = 0.0;
    int counted = 0;
    for (size_t k = 0; k < n_views; ++k) {
      for (int c = 0; c < 3 && own[k]; ++c) {
        change +=
            std::abs(t[k][c] - before[k][c]) / std::max(before[k][c], 1e-12);
        ++counted;
      }
    }
    out.report.lut_change = counted ? change / counted : 0.0;
    ++out.report.alternations;
    lut_converged = r.converged && r.usable;
  }
  if (lut && !joint) {
    for (int pass = 1; pass < options.max_alternations; ++pass) {
      std::vector<glm::dvec3> fr(n_views, glm::dvec3(0.0)),
          ff(n_views, glm::dvec3(0.0));
      for (size_t i = 0; i < samples.size(); ++i) {
        const glm::dvec3 f = LafortuneF1(best, samples.l[i], samples.v[i]);
        fr[samples.view[i]] += samples.weight[i] * f * samples.value[i];
        ff[samples.view[i]] += samples.weight[i] * f * f;
      }
      // A view whose f is (nearly) zero carries no information on T: keep
      // it rather than divide by ~0. T is a non-negative factor; it is kept
      // in [0, kMaxT].
      glm::dvec3 ff_max(0.0);
      for (const glm::dvec3& f : ff) ff_max = glm::max(ff_max, f);
      double change = 0.0;
      int counted = 0;
      for (size_t k = 0; k < n_views; ++k) {
        if (!own[k]) continue;
        for (int c = 0; c < 3; ++c) {
          if (!(ff[k][c] > 1e-12 * ff_max[c])) continue;  // no signal
          const double updated = std::clamp(fr[k][c] / ff[k][c], 0.0, kMaxT);
          change +=
              std::abs(updated - t[k][c]) / std::max(std::abs(t[k][c]), 1e-12);
          ++counted;
          t[k][c] = updated;
        }
      }
      out.report.lut_change = counted ? change / counted : 0.0;
      FollowOwnedViews(own, samples.views, &t);
      // Later passes start next to their solution: a few iterations do.
      LafortuneFitOptions later = options;
      later.max_iterations =
          std::min(options.max_iterations, kLaterPassIterations);
      LafortuneParams p = best;
      out.report.iterations += FitLobes(samples, t, later, false, peak_cap, &p);
      ++out.report.alternations;
      if (Finite(p)) best = p;
      if (out.report.lut_change < options.lut_threshold) {
        lut_converged = true;
        break;
      }
    }
  }
  if (!options.lookup_table) {
    out.report.converged = true;
    out.report.termination = "no lookup table: the lobes in one solve";
  } else if (!lut) {
    out.report.converged = true;
    out.report.termination =
        "no view has enough samples for a lookup-table entry: the lobes in one "
        "solve";
  } else if (joint) {
    out.report.converged = lut_converged;
    out.report.termination =
        lut_converged ? "joint lobe and lookup-table solve converged"
                      : "joint lobe and lookup-table solve: iteration cap "
                        "reached (raise --max-iterations)";
  } else if (lut_converged) {
    out.report.converged = true;
    out.report.termination = "lookup table converged";
  } else if (out.report.alternations < 2) {
    // The change is measured between alternations: one has none to show.
    out.report.termination =
        "alternation cap (" + std::to_string(options.max_alternations) +
        ") reached before the lookup table's change could be measured "
        "(raise --alternations)";
  } else {
    char why[200];
    std::snprintf(why, sizeof(why),
                  "alternation cap (%d) reached; the lookup table still "
                  "changed by %.3g (threshold %.3g; raise --alternations "
                  "or --lut-threshold)",
                  options.max_alternations, out.report.lut_change,
                  options.lut_threshold);
    out.report.termination = why;
  }
  // A first pass on a subsample is refined on all samples when no later
  // pass did (no lookup table, or a single alternation): a lobe fitted to a
  // quarter of the samples alone can be narrow and wrong between them.
  if (&first != &samples && out.report.alternations == 1) {
    LafortuneParams p = best;
    out.report.iterations += FitLobes(samples, t, options, false, peak_cap, &p);
    if (Finite(p)) best = p;
  }
  // Energy. At a stored view the albedo is T(v) times the bracket's
  // (models/albedo.h), so a T that would make the texel reflect more than
  // it receives there is lowered to the bound, T = 1 / albedo: a view the
  // lobes hardly reach otherwise takes a huge T. A texel still above 1
  // somewhere (the lobes' sum, or T between the stored views) is scaled
  // down until its largest albedo is 1, and says so.
  out.params.params = best;
  if (lut) {
    out.report.lut_views_at_energy_bound =
        BoundLookupTableByEnergy(best, samples.normal, samples.views, &t);
  }
  out.params.lut.color = t;
  const EnergyCheck energy = LafortuneEnergy(out.params);
  out.report.max_albedo = energy.max_albedo;
  out.report.max_albedo_at = DescribeEnergy(energy);
  if (energy.max_albedo > 1.0 && std::isfinite(energy.max_albedo)) {
    out.report.energy_scale = 1.0 / energy.max_albedo;
    ScaleLafortuneAlbedo(out.report.energy_scale, &best);
    out.params.params = best;
  }
  double se = 0.0, ss = 0.0;
  for (size_t i = 0; i < samples.size(); ++i) {
    const glm::dvec3 m =
        t[samples.view[i]] * LafortuneF1(best, samples.l[i], samples.v[i]);
    const glm::dvec3 d = m - samples.value[i];
    se += glm::dot(d, d);
    ss += glm::dot(samples.value[i], samples.value[i]);
  }
  out.report.final_cost = 0.5 * Cost(samples, t, best);
  out.report.rms = std::sqrt(se / (3.0 * samples.size()));
  out.report.relative_rms = ss > 0.0 ? std::sqrt(se / ss) : 0.0;
  out.report.usable = std::isfinite(out.report.rms);
  if (!out.report.usable) {
    out.report.message = LafortuneNonFiniteSample(samples, t, best);
    return out;
  }
  ReportLafortuneLimits(best, &out.report);
  return out;
}

}  // namespace clothfit
