#include "fitting/lafortune_covariance.h"

#include <ceres/jet.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>

#include "fitting/covariance_internal.h"

namespace clothfit {
namespace {

// The derivatives of a channel's bracket with respect to its entries
// (at most 1 + 4 * 3).
constexpr int kMaxChannelSize = 13;
using Jet = ceres::Jet<double, kMaxChannelSize>;

// The name of entry q of the channel layout (rho_d, then Cx, Cy, Cz, N
// per lobe) in channel c, as the report names it.
std::string EntryName(int q, int c) {
  if (q == 0) return std::string(kLafortuneDiffuse.name) + ChannelSuffix(c);
  const int k = (q - 1) / 4;
  return "lobes[" + std::to_string(k) + "]." +
         kLafortuneLobeEntries[(q - 1) % 4]->name + ChannelSuffix(c);
}

// W(v, j): the weight of fitted view owned[j] in view v's T (1 at a
// fitted view itself; LookupView's interpolation, linear in the entries,
// elsewhere).
std::vector<std::vector<double>> FollowWeights(
    const std::vector<glm::dvec3>& views, const std::vector<int>& owned) {
  std::vector<std::vector<double>> w(views.size(),
                                     std::vector<double>(owned.size(), 0.0));
  ViewTable unit;
  for (int k : owned) {
    unit.views.push_back(views[k]);
    unit.color.push_back(glm::dvec3(0.0));
    unit.alpha.push_back(1.0);
  }
  std::vector<bool> is_owned(views.size(), false);
  for (size_t j = 0; j < owned.size(); ++j) {
    is_owned[owned[j]] = true;
    w[owned[j]][j] = 1.0;
  }
  for (size_t j = 0; j < owned.size(); ++j) {
    unit.color[j] = glm::dvec3(1.0);
    for (size_t v = 0; v < views.size(); ++v) {
      if (!is_owned[v]) w[v][j] = LookupView(unit, views[v]).color.x;
    }
    unit.color[j] = glm::dvec3(0.0);
  }
  return w;
}

}  // namespace

void ReportLafortuneStddev(const TexelSamples& samples,
                           const LafortuneModel& model,
                           const std::vector<bool>& own, bool sigma_known,
                           FitReport* report) {
  if (report->energy_scale < 1.0 || report->lut_views_at_energy_bound > 0) {
    report->identifiability =
        "no standard deviations: the model is not the least-squares "
        "solution (it was lowered to conserve energy)";
    return;
  }
  const LafortuneParams& p = model.params;
  const int lobes = static_cast<int>(p.lobes.size());
  const int nx = LafortuneChannelSize(lobes);
  std::vector<int> owned;
  for (size_t k = 0; k < own.size(); ++k) {
    if (own[k]) owned.push_back(static_cast<int>(k));
  }
  // The gauge: T of the fitted views is t + D u with sum(D u) = 0
  // (columns e_j - e_last), so the table's mean stays where it is.
  const int nu = owned.empty() ? 0 : static_cast<int>(owned.size()) - 1;
  const int m = static_cast<int>(samples.size());
  // The Jacobian is dense (and its SVD holds two more of its size), and the
  // weights of the following views take owned^2 x following lookups:
  // beyond kMaxWork (1e7 Jacobian entries, 80 MB each) the fit gives
  // none, and says so.
  constexpr double kMaxWork = 1e7;
  const double following =
      static_cast<double>(samples.views.size() - owned.size());
  if (static_cast<double>(m) * (nx + nu) > kMaxWork ||
      static_cast<double>(owned.size()) * owned.size() * following >
          100.0 * kMaxWork) {
    report->identifiability =
        "no standard deviations: " + std::to_string(m) + " samples x " +
        std::to_string(nx + nu) + " parameters per channel (" +
        std::to_string(owned.size()) +
        " fitted views) is beyond the "
        "covariance's limit (1e7 Jacobian entries; fit a subset of the rows "
        "for them)";
    return;
  }
  const std::vector<std::vector<double>> follow =
      FollowWeights(samples.views, owned);
  std::map<std::string, ParameterReport*> by_name;
  for (ParameterReport& r : report->parameters) by_name[r.name] = &r;
  std::vector<std::string> not_identifiable;
  for (int c = 0; c < 3; ++c) {
    double xd[kMaxChannelSize];
    LafortuneChannelToArray(p, c, xd);
    Jet x[kMaxChannelSize];
    for (int q = 0; q < nx; ++q) x[q] = Jet(xd[q], q);
    Eigen::MatrixXd j = Eigen::MatrixXd::Zero(m, nx + nu);
    Eigen::VectorXd r(m);
    double cost = 0.0;
    for (int i = 0; i < m; ++i) {
      const glm::dvec3& l = samples.l[i];
      const glm::dvec3& v = samples.v[i];
      const Jet f1 = LobeSum(x, lobes, l.x * v.x, l.y * v.y, l.z * v.z) *
                     Foreshortening(l);
      const int view = samples.view[i];
      const double t = model.lut.color[view][c];
      const double s = std::sqrt(samples.weight[i][c]);
      r[i] = s * (t * f1.a - samples.value[i][c]);
      cost += 0.5 * r[i] * r[i];
      for (int q = 0; q < nx; ++q) j(i, q) = s * t * f1.v[q];
      for (int u = 0; u < nu; ++u) {
        j(i, nx + u) =
            s * f1.a * (follow[view][u] - follow[view][owned.size() - 1]);
      }
    }
    const ColumnCovariance cov =
        CovarianceOfColumns(j, r, sigma_known, cost, m);
    for (int col : cov.not_identifiable) {
      not_identifiable.push_back(
          col < nx ? EntryName(col, c)
                   : "lut.color[" + std::to_string(owned[col - nx]) + "]" +
                         ChannelSuffix(c));
    }
    // Conditional where some columns are not identifiable: those have
    // none (-1), the others' hold them at their values.
    for (int q = 0; q < nx; ++q) {
      const auto it = by_name.find(EntryName(q, c));
      if (it == by_name.end()) continue;
      it->second->stddev = cov.stddev[q];
      it->second->stddev_sandwich = cov.sandwich[q];
    }
    if (cov.conditional) report->stddev_conditional = true;
  }
  if (!not_identifiable.empty()) {
    report->identifiability = "not identifiable:";
    const size_t shown = std::min<size_t>(not_identifiable.size(), 6);
    for (size_t k = 0; k < shown; ++k) {
      report->identifiability += (k ? ", " : " ") + not_identifiable[k];
    }
    if (shown < not_identifiable.size()) {
      report->identifiability +=
          " and " + std::to_string(not_identifiable.size() - shown) + " more";
    }
    report->identifiability +=
        " (no standard deviation of their own: a lobe that does not shape "
        "the fit, or views' T trading with the lobes; try fewer lobes or "
        "--no-lut)";
  }
}

}  // namespace clothfit
