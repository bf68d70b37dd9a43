#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "fitting/energy_bound_fit_internal.h"

namespace clothfit {
namespace {

constexpr double kCos60 = 0.5;

bool Within(const TableRow& row, double c) {
  auto ok = [c](double z) { return z <= 0.0 || z >= c; };
  return ok(row.wi.z) && ok(row.wo.z);
}

}  // namespace

const MeasurementTable& FirstFitRows(const MeasurementTable& table,
                                     MeasurementTable* storage) {
  const size_t enough = std::max<size_t>(20, table.rows.size() / 10);
  for (double c : {kCos60, kEnergyBoundFadeCos}) {
    size_t n = 0;
    for (const TableRow& row : table.rows) n += Within(row, c) ? 1 : 0;
    if (n == table.rows.size()) return table;
    if (n < enough) continue;
    *storage = table;
    storage->rows.clear();
    for (const TableRow& row : table.rows) {
      if (Within(row, c)) storage->rows.push_back(row);
    }
    return *storage;
  }
  return table;
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

double RelativeFactorChange(const std::vector<double>& g,
                            const std::vector<double>& x) {
  double change = 0.0;
  for (size_t i = 0; i < g.size(); ++i) {
    change = std::max(change, std::abs(g[i] - x[i]) / std::max(x[i], 1e-300));
  }
  return change;
}

std::vector<double> AndersonFactors(
    const std::vector<std::vector<double>>& xs,
    const std::vector<std::vector<double>>& gs) {
  constexpr int kDepth = 3;
  const int k = static_cast<int>(gs.size()) - 1;  // the newest pair
  const int m = std::min(kDepth, k);
  const Eigen::Index n = static_cast<Eigen::Index>(gs[k].size());
  Eigen::VectorXd next = Eigen::Map<const Eigen::VectorXd>(gs[k].data(), n);
  if (m > 0) {
    // Minimise |r_k - dR gamma| over gamma, dR's columns the differences
    // of the residuals r_j = g_j - x_j, then x = g_k - dG gamma.
    auto r = [&](int j) {
      return Eigen::Map<const Eigen::VectorXd>(gs[j].data(), n) -
             Eigen::Map<const Eigen::VectorXd>(xs[j].data(), n);
    };
    Eigen::MatrixXd dr(n, m), dg(n, m);
    for (int c = 0; c < m; ++c) {
      const int j = k - m + c;
      dr.col(c) = r(j + 1) - r(j);
      dg.col(c) = Eigen::Map<const Eigen::VectorXd>(gs[j + 1].data(), n) -
                  Eigen::Map<const Eigen::VectorXd>(gs[j].data(), n);
    }
    const Eigen::VectorXd gamma = dr.colPivHouseholderQr().solve(r(k));
    if (gamma.allFinite()) next -= dg * gamma;
  }
  std::vector<double> out(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    out[i] = std::isfinite(next[i]) ? std::clamp(next[i], 1e-12, 1.0) : 1.0;
  }
  return out;
}

void ReportEnergyBound(const std::vector<double>& factors, int refits,
                       bool settled, FitReport* report) {
  int lowered = 0;
  double most = 0.0;
  for (double f : factors) {
    if (f < 1.0 - kEnergyBoundSettled) ++lowered;
    most = std::max(most, 1.0 - f);
  }
  char text[160];
  std::snprintf(text, sizeof(text),
                "lowers %d of %zu rows, by up to %.3g %%; %d refit(s)", lowered,
                factors.size(), 100.0 * most, refits);
  report->energy_bound = text;
  if (settled) return;
  report->converged = false;
  std::string msg =
      "the energy bound did not settle in " + std::to_string(refits) +
      " refits" +
      " (data brighter than a physical surface? check the table's "
      "calibration); the errors are the last refit's";
  if (!report->message.empty()) msg += "; " + report->message;
  report->message = msg;
}

}  // namespace clothfit
