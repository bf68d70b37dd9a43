// One Lafortune model for a whole table (Daubert et al. 2001, Section 5, one
// texel): the rows passed over rather than held, so that the samples are
// the fit's only copy of a large table.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include "fitting/direction_ids.h"
#include "fitting/lafortune_covariance.h"
#include "fitting/lafortune_mip.h"
#include "fitting/lafortune_samples.h"
#include "io/input_error.h"

namespace clothfit {
namespace {

// The values of a Lafortune model's table entries as report parameters
// ("diffuse_r", "lobes[1].N_b"), free, with their fit bounds: a lobe's C
// within its reach at the lobe's N (models/lafortune.h).
std::vector<ParameterReport> LafortuneParameterReports(
    const LafortuneParams& p) {
  std::vector<ParameterReport> out;
  auto add = [&](const ParamInfo& info, const std::string& prefix,
                 const glm::dvec3& field, const glm::dvec3* n) {
    for (int c = 0; c < 3; ++c) {
      ParameterReport r;
      r.name = prefix + info.name + ChannelSuffix(c);
      r.value = field[c];
      r.free = true;
      const bool c_entry = n != nullptr && &info != &kLafortuneN;
      r.upper = c_entry ? LafortuneLobeReach((*n)[c]) : info.fit_hi;
      r.lower = c_entry ? -r.upper : info.fit_lo;
      r.at_bound = OnFitBound(r.value, r.lower, r.upper);
      r.at_search_limit = r.at_bound && !info.physical;
      out.push_back(r);
    }
  };
  add(kLafortuneDiffuse, "", p.diffuse, nullptr);
  for (size_t k = 0; k < p.lobes.size(); ++k) {
    const std::string prefix = "lobes[" + std::to_string(k) + "].";
    VisitParamsConst(p.lobes[k],
                     [&](const ParamInfo& info, const glm::dvec3& field) {
                       add(info, prefix, field, &p.lobes[k].n);
                     });
  }
  return out;
}

// rms and relative_rms of `model` over the rows (LafortuneErrors), and its
// view_relative_rms with view_sums. `same_views`: the model's lookup table
// has the rows' views in order of first appearance. `rows_expected`: the
// rows the samples came from; a pass that sees another count read a file
// that changed.
void RowErrors(const TableRowPasses& rows, const LafortuneModel& model,
               bool same_views, bool view_sums, size_t rows_expected,
               FitReport* report) {
  LafortuneErrorSums sums(model, *rows.table, same_views, view_sums);
  ViewIds views;  // every row's view, as ViewIndex
  size_t count = 0;
  rows.each([&](const TableRow& row) {
    ++count;
    sums.Add(row, same_views || view_sums ? views.Id(row.wo) : 0);
  });
  if (count != rows_expected) {
    throw InputError(rows.table->source + ": changed while it was read (" +
                     std::to_string(rows_expected) + " rows, then " +
                     std::to_string(count) + ")");
  }
  sums.Finish(&report->rms, &report->relative_rms,
              view_sums ? &report->view_relative_rms : nullptr);
}

}  // namespace

LafortuneFitResult FitLafortuneRows(const TableRowPasses& rows,
                                    const LafortuneMipOptions& options) {
  const MeasurementTable& table = *rows.table;
  const Weighting weighting =
      LafortuneWeighting(table, options.noise, [&rows](int c) {
        std::vector<double> values;
        rows.each([&](const TableRow& row) {
          values.push_back(std::abs(row.value[c]));
        });
        return values;
      });
  // Without a lookup table (and without the views' coverage, alpha) the
  // fit needs no views: collected under one, it holds no per-view arrays
  // (T, alpha and their copies; a table of random directions has a view
  // a row).
  const bool one_view = !options.fit.lookup_table && !table.has_alpha;
  size_t count = 0, not_reflection = 0;
  bool any_weighted = false;
  int skipped = 0;
  TexelSamples samples;
  {
    SampleCollector collector(table, one_view);
    rows.each([&](const TableRow& row) {
      ++count;
      not_reflection += IsReflectionRow(row) ? 0 : 1;
      any_weighted = any_weighted || row.weight > 0.0;
      collector.Add(row, weighting);
    });
    samples = collector.Finish(&skipped);
  }
  RequireWeightedRows(table, any_weighted);
  CountNotReflection(table, not_reflection, count, "lafortune");

  // The candidates' errors over the rows, where they choose (the samples
  // are merged per light and view).
  const std::vector<int> lobes = LafortuneCandidateLobes(options);
  LafortuneCandidates candidates(options.tolerance);
  double seconds = 0.0;  // the solves'
  for (int k : lobes) {
    const auto start = std::chrono::steady_clock::now();
    LafortuneFitResult fit =
        FitLafortuneCandidate(samples, k, skipped, options);
    seconds +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
            .count();
    if (lobes.size() > 1) {
      RowErrors(rows, fit.params, !one_view, false, count, &fit.report);
    }
    if (candidates.Offer(std::move(fit))) break;
  }
  LafortuneFitResult fit = candidates.Take();
  fit.report.seconds = seconds;
  fit.report.parameters = LafortuneParameterReports(fit.params.params);
  if (fit.report.usable) {
    // The lobes' standard deviations at the table's gauge, with T free at
    // the views the fit gave an entry of their own.
    std::vector<bool> own(samples.views.size(), false);
    if (fit.report.lut_views_fitted > 0) {
      own = LafortuneOwnedViews(samples, options.fit.min_lut_samples);
    }
    ReportLafortuneStddev(samples, fit.params, own, weighting.LevelKnown(),
                          &fit.report);
  }
  samples = TexelSamples();  // released before the rows' pass
  // rms and relative_rms are of the rows, in the table's quantity, and the
  // views' error over every distinct view of the rows (LafortuneErrors).
  RowErrors(rows, fit.params, !one_view, true, count, &fit.report);
  // The cost is that of the table's values (sigma scales with the value's
  // conversion to rho, lafortune_samples.h), over the samples merged per
  // light and view. The level estimate counts the lobes' entries as free,
  // not the lookup table's.
  ReportWeighting(weighting, &fit.report);
  fit.report.minimised += std::string(" of the table's values (") +
                          QuantityName(table.quantity) +
                          "), over merged samples";
  // A lookup table of T = 1 and alpha = 1 at every view (a fit without
  // one, or one the data left at 1) is no table: the model is the same
  // without it (T(v) = 1, models/lafortune.h), and written it would hold
  // every distinct view of the table (10^7 for 10^7 rows of random
  // directions: gigabytes of JSON).
  const ViewTable& lut = fit.params.lut;
  const bool identity =
      std::all_of(lut.color.begin(), lut.color.end(),
                  [](const glm::dvec3& t) { return t == glm::dvec3(1.0); }) &&
      std::all_of(lut.alpha.begin(), lut.alpha.end(),
                  [](double a) { return a == 1.0; });
  if (identity) fit.params.lut = ViewTable();
  return fit;
}

LafortuneFitResult FitLafortuneTable(const MeasurementTable& table,
                                     const LafortuneMipOptions& options) {
  TableRowPasses rows;
  rows.table = &table;
  rows.each = [&table](const std::function<void(const TableRow&)>& row) {
    for (const TableRow& r : table.rows) row(r);
  };
  return FitLafortuneRows(rows, options);
}

}  // namespace clothfit
