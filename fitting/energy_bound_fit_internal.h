// Fits of the bounded thread and cloth (models/bounded.h): the model a fit
// writes carries the energy bound of its own parameters, so that it
// conserves energy everywhere on the hemisphere, and the fit must match
// that bounded model to the data, not the paper's model.
//
// The bound's tables are quadratures of the model at the parameters: the
// largest directional albedo over azimuth and channel at each node. With
// the azimuth, channel and rings of each entry held (the plan), the tables
// are smooth functions of the parameters, and the solve of the bounded
// model differentiates through them (fitting/energy_bound_tables_internal.h).
// After the solve the plan is found again at the result; the fit is done
// when the entries found afresh are those it was solved through (the
// largest albedos stayed where they were; MergeEnergyBoundPlans), else it
// is solved again through the merged plan. It starts from the paper's model
// fitted to every row (but those within 3 degrees of the horizon), or to
// the rows within 60 degrees (FirstFitRows), whichever fits every row
// better once bounded (ChooseBoundedStart): fitted to every row, the
// paper's model bends its parameters toward rows the bound lowers much (a
// thread table, whose thread exceeds albedo 1 from about 60 degrees), while the
// rows within 60 degrees leave grazing directions free (a measured table's
// few rows there). Where the bound lowers no row of the first, that fit is
// the bounded model's too. For fitting/*.cc only (not installed).
#pragma once

#include <cmath>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "fitting/energy.h"
#include "fitting/fit_result.h"
#include "fitting/start_search.h"
#include "io/table.h"
#include "models/bounded.h"

namespace clothfit {

// A row's factor below 1 - kEnergyBoundSettled is lowered by the bound;
// the most solves of the bounded model.
inline constexpr double kEnergyBoundSettled = 1e-6;
inline constexpr int kEnergyBoundRefits = 4;

// Relative excess of a table entry found afresh over the entry a solve went
// through that still counts as the same: the azimuth search's resolution
// (its refined step, 1.9 degrees) moves a peak's value by about 1e-5, and
// the tables' margin (kEnergyBoundMargin, 5 %) covers it.
inline constexpr double kEnergyBoundEntrySlack = 1e-3;

// The most peaks of an entry's albedo over azimuth a fit follows
// (EnergyBoundEntry::others and its azimuth).
inline constexpr size_t kEnergyBoundPeaks = 4;

// The rows of `table` with both cosines >= cos 60 degrees, or with the
// light or the view below the surface (where the bound does not act): a
// quarter of a table sampled uniformly over the hemisphere. When fewer
// than EnoughFirstFitRows, those within 87 degrees, else the whole table.
// Returns `table` itself or `*storage`.
const MeasurementTable& FirstFitRows(const MeasurementTable& table,
                                     MeasurementTable* storage);

// Half the sum of squared weighted residuals (fitting/residual_weight.h,
// sigma of the model's value where it depends on one) of `bounded` on
// every row of `table`: how two starts of the bounded model compare.
double BoundedCost(const MeasurementTable& table, const NoiseModel& noise,
                   const ModelParams& bounded);

// EnergyBoundFactor at every row (all 1 for a null bound).
std::vector<double> EnergyBoundFactors(const MeasurementTable& table,
                                       const EnergyBound* bound);

// Whether `bound` (may be null) lowers no row of `table`: every factor at
// least 1 - kEnergyBoundSettled.
bool LowersNoRow(const MeasurementTable& table, const EnergyBound* bound);

// The rows of `table` the bound leaves alone (light or view below the
// surface) or whose cosines are both at least c: `table` itself when that
// is every row or fewer than min_rows, else *storage. With c =
// kEnergyBoundFadeCos, the rows outside the horizon fade (within 3 degrees
// of the horizon: models/energy_bound.h), which any bound lowers.
const MeasurementTable& RowsWithin(const MeasurementTable& table, double c,
                                   size_t min_rows, MeasurementTable* storage);

// The fewest rows a first fit is made on (FirstFitRows, RowsWithin):
// max(20, a tenth of the table's rows).
size_t EnoughFirstFitRows(const MeasurementTable& table);

// The start of a bounded fit: the paper's model fitted to some rows, with
// its bound and the plan of that bound's entries (found once: the azimuth
// search is most of a bound's cost).
template <typename P>
struct BoundedStart {
  FitResult<P> fit;
  bool of_every_row = true;  // else fitted to FirstFitRows
  // Fitted to every row of the table itself: not to its sample
  // (SearchTable: a table of more than kSampleRows rows), which the
  // bounded solves then refine on every row, nor without its rows in the
  // horizon fade.
  bool of_table = true;
  std::shared_ptr<const EnergyBound> bound;
  EnergyBoundPlan plan;
};

// The better start of the bounded model: the paper's model fitted to every
// row outside the horizon fade (fit_rows(rows, true)), or to FirstFitRows
// where the table has rows beyond them (fit_rows(rows, false)), whichever
// is usable and of the lower BoundedCost once bounded (the fit of every
// row where equal). fit_rows(rows, every) fits the paper's model to
// `rows`.
//
// The rows in the horizon fade are left out of the first: any bound fades
// them toward 0, and the paper's model fitted to them is pulled toward
// values a bounded surface does not reflect (on a synth table of the
// bounded linen, 20,000 rows: 160 iterations and 26 s, in a basin of 10^5
// x the cost of the rows within 60 degrees). A table of more than
// kSampleRows rows is represented by its sample (SearchTable, the rows the
// solves' starts see): the starts are only starts, and the bounded solves
// refine on every row.
template <typename P>
BoundedStart<P> ChooseBoundedStart(
    const MeasurementTable& whole, const NoiseModel& noise,
    const std::function<FitResult<P>(const MeasurementTable&, bool)>&
        fit_rows) {
  MeasurementTable sample_storage;
  const MeasurementTable& table = SearchTable(whole, &sample_storage);
  const bool sampled = &table != &whole;
  const auto bounded = [&](FitResult<P> fit, bool of_table) {
    BoundedStart<P> start;
    start.of_table = of_table && !sampled;
    fit.report.rows = static_cast<int>(whole.rows.size());
    start.bound = EnergyBoundOf(fit.params, &start.plan);
    start.fit = std::move(fit);
    return start;
  };
  const auto cost = [&](const BoundedStart<P>& start) {
    P p = start.fit.params;
    p.energy_bound = start.bound;
    return BoundedCost(table, noise, ModelParams(p));
  };
  MeasurementTable outside_storage;
  const MeasurementTable& outside = RowsWithin(
      table, kEnergyBoundFadeCos, EnoughFirstFitRows(table), &outside_storage);
  const bool outside_is_table = &outside == &table;
  FitResult<P> every_fit = fit_rows(outside, true);
  MeasurementTable first_storage;
  const MeasurementTable& first = FirstFitRows(table, &first_storage);
  // (FirstFitRows are among those outside the fade: as many are the same.)
  if (first.rows.size() == outside.rows.size()) {
    return bounded(std::move(every_fit), outside_is_table);
  }
  // Where the fit of every row converged and its bound lowers none of
  // them, that fit is the bounded model's (SettleEnergyBound): no other
  // start is needed. (One stopped at a search limit may be a poor basin,
  // which the rows within 60 degrees avoid: the thread test's table.)
  std::optional<BoundedStart<P>> every;
  if (every_fit.report.usable) {
    const bool converged = every_fit.report.converged;
    every = bounded(std::move(every_fit), outside_is_table);
    if (converged && every->of_table &&
        LowersNoRow(table, every->bound.get())) {
      return std::move(*every);
    }
  }
  FitResult<P> within_fit = fit_rows(first, false);
  if (!within_fit.report.usable) {
    return every ? std::move(*every)
                 : bounded(std::move(every_fit), outside_is_table);
  }
  BoundedStart<P> within = bounded(std::move(within_fit), false);
  within.of_every_row = false;
  if (!every) return within;  // its bound not searched
  return cost(within) < cost(*every) ? within : std::move(*every);
}

// Marks held (EnergyBoundEntry::held) every entry of `plan` that no row's
// factor depends on, nor would if the model were 25 % brighter: the
// entries about a row's cosines where its light table exceeds 0.8 c or
// its view table 0.8, by `tables` (the plan's at the solve's start). An
// entry that a row comes to depend on during the solve is found afterwards
// (MergeEnergyBoundPlans) and solved again with its derivative.
void HoldUnusedEntries(const MeasurementTable& table, const EnergyBound& tables,
                       EnergyBoundPlan* plan);

// After a solve through `*plan` ending at p, whose tables there are
// `*bound`: whether the plan found afresh at p (`fresh`, its entries held
// where the rows of `table` do not depend on them) agrees with it for the
// rows: every entry the rows depend on (derived in the solve, or by the
// fresh plan) found afresh at most kEnergyBoundEntrySlack above the solved
// one, and derived in the solve. An entry neither plan has the rows depend
// on may come out above (the parameters moved far from where the plan was
// found, and no row's factor follows it); it is raised in *bound all the
// same, and the fit agrees as long as every row's factor stays as solved.
// The entries found above or underived take the fresh plan's place in
// *plan, and *bound is the larger of the two tables entry by entry (so
// that it conserves energy).
template <typename P>
bool MergeEnergyBoundPlans(const MeasurementTable& table, const P& p,
                           const EnergyBoundPlan& fresh, EnergyBoundPlan* plan,
                           std::shared_ptr<const EnergyBound>* bound) {
  const std::shared_ptr<const EnergyBound> found = EnergyBoundByPlan(p, fresh);
  auto merged = std::make_shared<EnergyBound>(**bound);
  bool same = true, raised = false;
  for (int side = 0; side < 2; ++side) {
    auto& entries = side == 0 ? plan->light : plan->view;
    const auto& fresh_entries = side == 0 ? fresh.light : fresh.view;
    const std::vector<double>& now = side == 0 ? found->light : found->view;
    std::vector<double>& out = side == 0 ? merged->light : merged->view;
    for (size_t k = 0; k < entries.size(); ++k) {
      const bool above = now[k] > out[k] * (1.0 + kEnergyBoundEntrySlack);
      const bool underived = !fresh_entries[k].held && entries[k].held;
      const bool idle = entries[k].held && fresh_entries[k].held;
      if (underived || (above && !idle)) same = false;
      if (above && !idle) {
        // Another peak rose above the one the solve followed: the next
        // follows both (and the earlier ones), at most kEnergyBoundPeaks.
        // (A peak within a crest step of the new one is that one.)
        std::vector<double> peaks;
        auto keep = [&](double phi) {
          const double apart =
              std::remainder(phi - fresh_entries[k].phi, 2.0 * kPi);
          if (std::abs(apart) > kEnergyBoundCrestStep &&
              peaks.size() + 1 < kEnergyBoundPeaks) {
            peaks.push_back(phi);
          }
        };
        keep(entries[k].phi);
        for (double phi : entries[k].others) keep(phi);
        const bool same_channel =
            entries[k].channel == fresh_entries[k].channel;
        entries[k] = fresh_entries[k];
        if (same_channel) entries[k].others = peaks;
      } else if (above || underived) {
        entries[k] = fresh_entries[k];
      }
      if (above) {
        out[k] = now[k];
        raised = true;
      }
    }
  }
  if (same && raised) {  // only idle entries raised: the rows must not see it
    for (size_t i = 0; i < table.rows.size() && same; ++i) {
      const TableRow& row = table.rows[i];
      const double solved = EnergyBoundFactor(bound->get(), row.wi.z, row.wo.z);
      const double now = EnergyBoundFactor(merged.get(), row.wi.z, row.wo.z);
      same = std::abs(now - solved) <= 1e-12 * solved;
    }
  }
  if (raised) *bound = merged;
  return same;
}

// The largest factor on the model (its `scale`, fitted with --fit-scale)
// that still has an effect through the bound whose tables at the model's
// current scale `scale` are `tables`: the bound takes the model at
// max(1, scale), so above 1 a row's factor divides the scale out once the
// row's albedo reaches 1, and above the largest such threshold over the
// rows (max(1, scale) / the row's albedo), and at least 1, the scale
// changes no row. A solve would wander along it without end (the data
// brighter than the bounded model can reflect). HUGE_VAL where some
// reflection row is not bounded by the tables at all (albedo 0).
double EnergyBoundScaleCap(const MeasurementTable& table,
                           const EnergyBound& tables, double scale);

// Where a fitted scale ended at its cap (EnergyBoundScaleCap; the
// report's parameter "scale" at its bound): not converged, and the message
// says why.
void ReportScaleCap(double scale, double cap, FitReport* report);

// Records in the report what the bound did: how many rows it lowers and by
// how much, the solves it took; when it did not settle within
// kEnergyBoundRefits solves, the fit is not converged and the message says
// so.
void ReportEnergyBound(const MeasurementTable& table, const EnergyBound* bound,
                       int refits, bool settled, FitReport* report);

// The fit of the bounded model from `start` (ChooseBoundedStart):
// refit(plan, from, search_bound, scale_cap) solves the bounded model, its
// tables through `plan`, from the parameters `from` and, with
// search_bound, from the start search too, done through that bound's
// fixed factors of the rows (the first solve: the first fit's rows may
// not tell a weak thread's parameters, nor its basin be that of every
// row; the search sees the sample's rows, so no factor of every row is
// held through the solves: 76 MiB at 10^7 rows); a
// fitted scale stays at most scale_cap (EnergyBoundScaleCap at `from`).
// Returns the last solve with its bound attached (the tables it was solved
// through), its report the bound's effect, the iterations of all solves and
// the furnace check.
template <typename P>
FitResult<P> SettleEnergyBound(
    const MeasurementTable& table,
    const std::function<FitResult<P>(const EnergyBoundPlan&, const P&,
                                     const EnergyBound*, double)>& refit,
    BoundedStart<P> start) {
  FitResult<P> result = std::move(start.fit);
  FitResult<P>* fit = &result;
  EnergyBoundPlan plan = std::move(start.plan);
  std::shared_ptr<const EnergyBound> bound = std::move(start.bound);
  // Where the bound lowers no row, the paper's model's fit (of the table
  // itself) is the bounded model's.
  bool settled =
      start.of_every_row && start.of_table && LowersNoRow(table, bound.get());
  int refits = 0, iterations = fit->report.iterations;
  double scale_cap = HUGE_VAL;  // the last solve's
  const int starts = fit->report.starts;
  const std::string search = fit->report.search;  // the first fit's
  while (!settled && refits < kEnergyBoundRefits) {
    if (!fit->report.usable) return result;
    const std::shared_ptr<const EnergyBound> tables =
        EnergyBoundByPlan(fit->params, plan);
    HoldUnusedEntries(table, *tables, &plan);
    const P from = fit->params;
    scale_cap = EnergyBoundScaleCap(table, *tables, from.scale);
    *fit = refit(plan, from, refits == 0 ? bound.get() : nullptr, scale_cap);
    iterations += fit->report.iterations;
    ++refits;
    // The tables it was solved through (its plan refined to the crests at
    // its last point, as the solve's tables were), against those found
    // afresh.
    plan = RefineEnergyBoundPlanAt(fit->params, plan);
    bound = EnergyBoundByPlan(fit->params, plan);
    EnergyBoundPlan fresh_plan;
    EnergyBoundOf(fit->params, &fresh_plan);
    HoldUnusedEntries(table, *bound, &fresh_plan);
    settled =
        MergeEnergyBoundPlans(table, fit->params, fresh_plan, &plan, &bound);
  }
  fit->report.iterations = iterations;
  fit->report.starts = starts;
  fit->report.search = search;
  fit->params.energy_bound = bound;
  ReportEnergyBound(table, bound.get(), refits, settled, &fit->report);
  ReportScaleCap(fit->params.scale, scale_cap, &fit->report);
  ReportModelEnergy(ModelParams(fit->params), &fit->report);
  return result;
}

}  // namespace clothfit
