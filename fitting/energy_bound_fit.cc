#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "fitting/energy_bound_fit_internal.h"
#include "fitting/residual_weight.h"
#include "models/evaluate.h"

namespace clothfit {
namespace {

constexpr double kCos60 = 0.5;

// Whether the bound leaves the row alone (light or view below the
// surface) or both its cosines are at least c.
bool Within(const TableRow& row, double c) {
  const double ci = row.wi.z, co = row.wo.z;
  return !(ci > 0.0 && co > 0.0) || (ci >= c && co >= c);
}

size_t CountWithin(const MeasurementTable& table, double c) {
  size_t n = 0;
  for (const TableRow& row : table.rows) n += Within(row, c) ? 1 : 0;
  return n;
}

// *storage: `table` with only its rows Within c.
const MeasurementTable& CopyWithin(const MeasurementTable& table, double c,
                                   MeasurementTable* storage) {
  *storage = table;
  storage->rows.clear();
  for (const TableRow& row : table.rows) {
    if (Within(row, c)) storage->rows.push_back(row);
  }
  return *storage;
}

}  // namespace

const MeasurementTable& RowsWithin(const MeasurementTable& table, double c,
                                   size_t min_rows, MeasurementTable* storage) {
  const size_t n = CountWithin(table, c);
  if (n == table.rows.size() || n < min_rows) return table;
  return CopyWithin(table, c, storage);
}

size_t EnoughFirstFitRows(const MeasurementTable& table) {
  return std::max<size_t>(20, table.rows.size() / 10);
}

const MeasurementTable& FirstFitRows(const MeasurementTable& table,
                                     MeasurementTable* storage) {
  const size_t enough = EnoughFirstFitRows(table);
  for (double c : {kCos60, kEnergyBoundFadeCos}) {
    const size_t n = CountWithin(table, c);
    if (n == table.rows.size()) return table;
    if (n >= enough) return CopyWithin(table, c, storage);
  }
  return table;
}

double BoundedCost(const MeasurementTable& table, const NoiseModel& noise,
                   const ModelParams& bounded) {
  const Weighting weighting(table, noise);
  double cost = 0.0;
  for (const TableRow& row : table.rows) {
    const glm::dvec3 m = Evaluate(bounded, row.wi, row.wo, table.quantity);
    const glm::dvec3 scale = weighting.DependsOnModel()
                                 ? weighting.ScaleAt(row, m)
                                 : weighting.Scale(row);
    for (int c = 0; c < table.channels; ++c) {
      const double r = WeightedResidual(m[c], row.value[c], scale[c]);
      cost += 0.5 * r * r;
    }
  }
  return std::isfinite(cost) ? cost : HUGE_VAL;
}

std::vector<double> EnergyBoundFactors(const MeasurementTable& table,
                                       const EnergyBound* bound) {
  std::vector<double> f(table.rows.size(), 1.0);
  if (bound == nullptr) return f;
  for (size_t i = 0; i < f.size(); ++i) {
    f[i] = EnergyBoundFactor(bound, table.rows[i].wi.z, table.rows[i].wo.z);
  }
  return f;
}

bool LowersNoRow(const MeasurementTable& table, const EnergyBound* bound) {
  if (bound == nullptr) return true;
  for (const TableRow& row : table.rows) {
    const double g = EnergyBoundFactor(bound, row.wi.z, row.wo.z);
    if (!(g >= 1.0 - kEnergyBoundSettled)) return false;
  }
  return true;
}

void HoldUnusedEntries(const MeasurementTable& table, const EnergyBound& tables,
                       EnergyBoundPlan* plan) {
  const int n = static_cast<int>(plan->light.size());
  std::vector<bool> used(2 * n, false);  // light then view
  // The nodes about cosine c (energy_bound_internal::Interpolate), a copy
  // standing for the first node it copies.
  auto mark = [&](int side, double c) {
    const double x = std::sqrt(std::clamp(c, 0.0, 1.0)) * (n - 1);
    const int k = std::min(n - 2, static_cast<int>(x));
    for (int j : {k, k + 1}) {
      const auto& entries = side == 0 ? plan->light : plan->view;
      while (j + 1 < n && entries[j].copy) ++j;
      used[side * n + j] = true;
    }
  };
  for (const TableRow& row : table.rows) {
    const double ci = row.wi.z, co = row.wo.z;
    if (!(ci > 0.0) || !(co > 0.0)) continue;
    const double l =
        energy_bound_internal::Interpolate<double>(tables.light.data(), n, ci);
    const double v =
        energy_bound_internal::Interpolate<double>(tables.view.data(), n, co);
    if (l > 0.8 * ci) mark(0, ci);
    if (v > 0.8) mark(1, co);
  }
  for (int side = 0; side < 2; ++side) {
    auto& entries = side == 0 ? plan->light : plan->view;
    for (int k = 0; k < n; ++k) entries[k].held = !used[side * n + k];
  }
}

double EnergyBoundScaleCap(const MeasurementTable& table,
                           const EnergyBound& tables, double scale) {
  double cap = 0.0;
  for (const TableRow& row : table.rows) {
    if (!(row.wi.z > 0.0 && row.wo.z > 0.0)) continue;
    const double albedo = EnergyBoundAlbedo(tables, row.wi.z, row.wo.z);
    if (!(albedo > 0.0)) return HUGE_VAL;
    cap = std::max(cap, std::max(1.0, scale) / albedo);
  }
  // At most 1, the scale dims the bounded model (the bound is the
  // model's at 1): it always has an effect there.
  return cap > 0.0 ? std::max(1.0, cap) : HUGE_VAL;
}

void ReportEnergyBound(const MeasurementTable& table, const EnergyBound* bound,
                       int refits, bool settled, FitReport* report) {
  int lowered = 0;
  double most = 0.0;
  for (const TableRow& row : table.rows) {
    const double f = EnergyBoundFactor(bound, row.wi.z, row.wo.z);
    if (f < 1.0 - kEnergyBoundSettled) ++lowered;
    most = std::max(most, 1.0 - f);
  }
  char text[160];
  std::snprintf(text, sizeof(text),
                "lowers %d of %zu rows, by up to %.3g %%; %d solve(s) of the "
                "bounded model",
                lowered, table.rows.size(), 100.0 * most, refits);
  report->energy_bound = text;
  if (settled) return;
  report->converged = false;
  std::string msg =
      "the energy bound did not settle in " + std::to_string(refits) +
      " solves (its largest albedos moved to other directions each time); "
      "the errors are the last solve's";
  if (!report->message.empty()) msg += "; " + report->message;
  report->message = msg;
}

void ReportScaleCap(double scale, double cap, FitReport* report) {
  if (!(scale >= cap * (1.0 - 1e-9))) return;  // cap HUGE_VAL: never
  bool fitted = false;  // a scale held at 1 may equal a cap of 1
  for (const ParameterReport& p : report->parameters) {
    fitted = fitted || (p.name == "scale" && p.at_bound);
  }
  if (!fitted) return;
  report->converged = false;
  char text[240];
  std::snprintf(text, sizeof(text),
                "the scale reached %.4g, above which the energy bound divides "
                "it out of every row: the data are brighter than the bounded "
                "model reflects",
                cap);
  std::string msg = text;
  if (!report->message.empty()) msg += "; " + report->message;
  report->message = msg;
}

}  // namespace clothfit
