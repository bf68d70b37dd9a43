// Fits of the bounded thread and cloth (models/bounded.h): the model a fit
// writes carries the energy bound of its own parameters, so that it
// conserves energy everywhere on the hemisphere, and the fit must match
// that bounded model to the data, not the paper's model.
//
// The bound's tables are a quadrature of the model at the parameters, so
// they are held fixed during a solve: the rows' bound factors
// EnergyBoundFactor(bound, wi.z, wo.z) multiply the model as constants,
// and the fit is repeated until the factors of its result's bound are the
// factors it was fitted through (a fixed point, within kEnergyBoundSettled
// relative). Plain repetition settles slowly, since the bound divides the
// model's own brightness out (fitting a brighter model gives a stronger
// bound); the factors are therefore mixed by Anderson acceleration
// (Walker and Ni 2011, "Anderson acceleration for fixed-point
// iterations", depth 3).
//
// The first fit, of the paper's model, uses only the rows with light and
// view within 60 degrees of the normal (FirstFitRows), where a model of
// plausible brightness is not bounded: fitted to every row, the unbounded
// model bends its parameters to follow the bounded grazing rows, and the
// repetition may settle in that bent basin. Includes Ceres' Eigen: for
// fitting/*.cc only.
#pragma once

#include <cmath>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "fitting/energy.h"
#include "fitting/fit_result.h"
#include "io/table.h"
#include "models/bounded.h"

namespace clothfit {

// Largest relative change of the factors between two refits that counts
// as settled, and the most refits.
inline constexpr double kEnergyBoundSettled = 1e-6;
inline constexpr int kEnergyBoundRefits = 10;

// The rows of `table` with both cosines >= cos 60 degrees, or <= 0 (where
// the bound does not act): a quarter of a table sampled uniformly over the
// hemisphere. When fewer than max(20, a tenth of the rows), those within 87
// degrees, else the whole table. Returns `table` itself or `*storage`.
const MeasurementTable& FirstFitRows(const MeasurementTable& table,
                                     MeasurementTable* storage);

// EnergyBoundFactor at every row (all 1 for a null bound).
std::vector<double> EnergyBoundFactors(const MeasurementTable& table,
                                       const EnergyBound* bound);

// The next factors from the history of the refits: xs[k] the factors refit
// k was fitted through, gs[k] the factors of its result's bound (equal
// sizes, at least 1 pair). Anderson mixing over the last 3 differences;
// clamped to [1e-12, 1] (the bound only lowers).
std::vector<double> AndersonFactors(const std::vector<std::vector<double>>& xs,
                                    const std::vector<std::vector<double>>& gs);

// Largest |g - x| / x over the rows.
double RelativeFactorChange(const std::vector<double>& g,
                            const std::vector<double>& x);

// Records in the report what the bound did: how many rows it lowers and by
// how much, the refits it took; when it did not settle within
// kEnergyBoundRefits refits, the fit is not converged and the message says
// so.
void ReportEnergyBound(const std::vector<double>& factors, int refits,
                       bool settled, FitReport* report);

// The fixed point above, from `*fit` (the first fit, of FirstFitRows):
// refit(factors, from, search) fits `table` through the rows' factors
// from the parameters `from`, and (`search` true, the first refit) from
// the start search too, done through the factors: the first fit's rows
// may not tell a weak thread's parameters, and its basin need not be the
// one of every row. Each solve has the solver's own iteration limit. On
// return *fit holds the last refit with its bound attached, and its report
// the bound's effect, the iterations of all solves, the starts of every
// search and the furnace check.
template <typename P>
void SettleEnergyBound(
    const MeasurementTable& table,
    const std::function<FitResult<P>(const std::vector<double>&, const P&,
                                     bool)>& refit,
    FitResult<P>* fit) {
  std::vector<std::vector<double>> xs, gs;
  std::shared_ptr<const EnergyBound> bound;
  bool settled = false;
  int refits = 0, iterations = fit->report.iterations;
  int starts = fit->report.starts;
  const std::string search = fit->report.search;  // the first fit's
  for (;;) {
    if (!fit->report.usable) return;
    bound = EnergyBoundOf(fit->params);
    std::vector<double> g = EnergyBoundFactors(table, bound.get());
    if (!xs.empty()) {
      gs.push_back(g);
      if (RelativeFactorChange(g, xs.back()) <= kEnergyBoundSettled) {
        settled = true;
        break;
      }
    }
    if (refits == kEnergyBoundRefits) break;
    xs.push_back(xs.empty() ? g : AndersonFactors(xs, gs));
    const P from = fit->params;
    *fit = refit(xs.back(), from, true);
    iterations += fit->report.iterations;
    if (refits == 0) starts += fit->report.starts - 1;  // `from` counted
    ++refits;
  }
  fit->report.iterations = iterations;
  fit->report.starts = starts;
  fit->report.search = search;
  fit->params.energy_bound = bound;
  ReportEnergyBound(
      gs.empty() ? EnergyBoundFactors(table, bound.get()) : gs.back(), refits,
      settled, &fit->report);
  ReportModelEnergy(ModelParams(fit->params), &fit->report);
}

}  // namespace clothfit
