#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include "fitting/ceres_linear_solver_internal.h"
#include "fitting/lafortune_bounds_internal.h"
#include "fitting/lafortune_joint_internal.h"
#include "fitting/residual_weight.h"
#include "models/lafortune.h"

namespace clothfit {
namespace {

// <f1, f1>_w of a view below which the lobes do not reach it (T = 1).
constexpr double kNoReach = 1e-250;

// factor: the foreshortening max(l_z, 0) alone (T is a parameter here).
using SampleTerms = LafortuneSampleTerms;

// The least-squares factor fy / ff of a view, in [0, max_t], computed
// without dividing by a vanishing ff (whose reciprocal, in a Jet's
// derivative, is not finite): a view the lobes hardly reach takes
// max_t, one they do not reach at all 1.
template <typename T>
T ProjectedFactor(const T& fy, const T& ff, double max_t) {
  if (!(ff > T(kNoReach))) return T(1.0);
  if (!(fy > T(0.0))) return T(0.0);
  if (!(fy < T(max_t) * ff)) return T(max_t);
  return fy / ff;
}

// The residuals of one view's samples, T(v) f1(l, v) - y weighted
// (fitting/residual_weight.h; eq. 3). For a view with an entry of its own
// T(v) is the closed-form least-squares factor of the current lobes,
// <f1, y>_w / <f1, f1>_w in [0, max_t] (eq. 4), differentiated through:
// the residual is that of the lobes with T projected out (variable
// projection, Golub and Pereyra 1973); for another view it is the fixed
// t.
// The variables are the bounded ones (fitting/lafortune_bounds_internal.h).
template <int kLobes>
struct ViewResidual {
  const std::vector<SampleTerms> terms;
  const bool own;
  const double fixed_t, max_t, peak_cap;

  template <typename T>
  bool operator()(const T* y, T* residual) const {
    T x[1 + 4 * kLobes];
    LobesFromBounded(y, kLobes, peak_cap, x);
    for (size_t i = 0; i < terms.size(); ++i) {
      const SampleTerms& s = terms[i];
      residual[i] = LobeSum(x, kLobes, s.xx, s.yy, s.zz) * s.factor;
    }
    T t(fixed_t);
    if (own) {
      T fy(0.0), ff(0.0);
      for (size_t i = 0; i < terms.size(); ++i) {
        const double w = terms[i].scale * terms[i].scale;
        fy += w * residual[i] * terms[i].measured;
        ff += w * residual[i] * residual[i];
      }
      t = ProjectedFactor(fy, ff, max_t);
    }
    for (size_t i = 0; i < terms.size(); ++i) {
      residual[i] =
          WeightedResidual(t * residual[i], terms[i].measured, terms[i].scale);
    }
    return true;
  }

  static ceres::CostFunction* Create(std::vector<SampleTerms> terms, bool own,
                                     double fixed_t, double max_t,
                                     double peak_cap) {
    const int n = static_cast<int>(terms.size());
    return new ceres::AutoDiffCostFunction<ViewResidual, ceres::DYNAMIC,
                                           1 + 4 * kLobes>(
        new ViewResidual{std::move(terms), own, fixed_t, max_t, peak_cap}, n);
  }

  // The factor of the bounded variables y for this view: what the
  // residual uses.
  double Factor(const double* y) const {
    if (!own) return fixed_t;
    double x[1 + 4 * kLobes];
    LobesFromBounded(y, kLobes, peak_cap, x);
    double fy = 0.0, ff = 0.0;
    for (size_t i = 0; i < terms.size(); ++i) {
      const double f =
          LobeSum(x, kLobes, terms[i].xx, terms[i].yy, terms[i].zz) *
          terms[i].factor;
      const double w = terms[i].scale * terms[i].scale;
      fy += w * f * terms[i].measured;
      ff += w * f * f;
    }
    return ProjectedFactor(fy, ff, max_t);
  }
};

// The lobe count is a template argument: the solver's inner loop unrolls.
template <int kLobes>
void AddViews(const std::vector<std::vector<SampleTerms>>& by_view,
              const std::vector<bool>& own, const std::vector<double>& lut,
              double max_t, double peak_cap, double* x,
              ceres::Problem* problem) {
  for (size_t k = 0; k < by_view.size(); ++k) {
    if (by_view[k].empty()) continue;
    problem->AddResidualBlock(ViewResidual<kLobes>::Create(
                                  by_view[k], own[k], lut[k], max_t, peak_cap),
                              nullptr, x);
  }
}

template <int kLobes>
void Factors(const std::vector<std::vector<SampleTerms>>& by_view,
             const std::vector<bool>& own, double max_t, double peak_cap,
             const double* x, std::vector<double>* lut) {
  for (size_t k = 0; k < by_view.size(); ++k) {
    if (by_view[k].empty() || !own[k]) continue;
    const ViewResidual<kLobes> r{by_view[k], true, 1.0, max_t, peak_cap};
    (*lut)[k] = r.Factor(x);
  }
}

}  // namespace

JointChannelResult SolveJointChannel(const TexelSamples& samples,
                                     const std::vector<bool>& own, int channel,
                                     int lobes,
                                     const LafortuneFitOptions& options,
                                     double max_t, double peak_cap, double* x,
                                     std::vector<double>* lut) {
  JointChannelResult out;
  const size_t n_views = lut->size();
  std::vector<double> y = LobesToBounded(x, lobes, peak_cap);
  LobesFromBounded(y.data(), lobes, peak_cap, x);
  std::vector<std::vector<SampleTerms>> by_view(n_views);
  double start_cost = 0.0;
  for (size_t i = 0; i < samples.size(); ++i) {
    const glm::dvec3& l = samples.l[i];
    const glm::dvec3& v = samples.v[i];
    const int view = samples.view[i];
    const SampleTerms s = {l.x * v.x,
                           l.y * v.y,
                           l.z * v.z,
                           Foreshortening(l),
                           samples.value[i][channel],
                           std::sqrt(samples.weight[i][channel])};
    by_view[view].push_back(s);
    const double d =
        (*lut)[view] * LobeSum(x, lobes, s.xx, s.yy, s.zz) * s.factor -
        s.measured;
    start_cost += s.scale * s.scale * d * d;
  }
  // Ceres refuses (and logs) a start whose cost is not finite.
  if (!std::isfinite(start_cost)) return out;
  ceres::Problem problem;
  double* const v = y.data();
  problem.AddParameterBlock(v, LafortuneChannelSize(lobes));
  switch (lobes) {
    case 0:
      AddViews<0>(by_view, own, *lut, max_t, peak_cap, v, &problem);
      break;
    case 1:
      AddViews<1>(by_view, own, *lut, max_t, peak_cap, v, &problem);
      break;
    case 2:
      AddViews<2>(by_view, own, *lut, max_t, peak_cap, v, &problem);
      break;
    default:
      AddViews<3>(by_view, own, *lut, max_t, peak_cap, v, &problem);
  }
  SetBoundedLobeBounds(lobes, v, &problem);
  ceres::Solver::Options solver;
  SetCeresLinearSolver(options.linear_solver, &solver);
  solver.max_num_iterations = options.max_iterations;
  solver.function_tolerance = options.joint_function_tolerance;
  solver.parameter_tolerance = 1e-10;
  SkipProjectedLineSearch(&solver);
  solver.num_threads = 1;
  solver.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(solver, &problem, &summary);
  out.iterations = static_cast<int>(summary.iterations.size());
  out.converged = summary.termination_type == ceres::CONVERGENCE;
  out.usable = summary.IsSolutionUsable() && std::isfinite(summary.final_cost);
  if (!out.usable) return out;
  LobesFromBounded(v, lobes, peak_cap, x);
  switch (lobes) {  // the table of the solution
    case 0:
      Factors<0>(by_view, own, max_t, peak_cap, v, lut);
      break;
    case 1:
      Factors<1>(by_view, own, max_t, peak_cap, v, lut);
      break;
    case 2:
      Factors<2>(by_view, own, max_t, peak_cap, v, lut);
      break;
    default:
      Factors<3>(by_view, own, max_t, peak_cap, v, lut);
  }
  return out;
}

void FollowOwnedViews(const std::vector<bool>& own,
                      const std::vector<glm::dvec3>& views,
                      std::vector<glm::dvec3>* t) {
  ViewTable owned;
  for (size_t k = 0; k < views.size(); ++k) {
    if (!own[k]) continue;
    owned.views.push_back(views[k]);
    owned.color.push_back((*t)[k]);
    owned.alpha.push_back(1.0);
  }
  for (size_t k = 0; k < views.size(); ++k) {
    if (!own[k]) (*t)[k] = LookupView(owned, views[k]).color;
  }
}

JointChannelResult SolveJoint(const TexelSamples& on,
                              const std::vector<bool>& own,
                              const LafortuneFitOptions& options, double max_t,
                              double peak_cap, LafortuneParams* p,
                              std::vector<glm::dvec3>* t) {
  JointChannelResult out;
  out.usable = true;
  const int lobes = static_cast<int>(p->lobes.size());
  const size_t n_views = t->size();
  bool all_own = true;
  for (size_t k = 0; k < n_views; ++k) all_own = all_own && own[k];
  const int rounds = all_own ? 1 : 2;
  for (int round = 0; round < rounds && out.usable; ++round) {
    out.converged = true;
    for (int c = 0; c < 3; ++c) {
      std::vector<double> x(LafortuneChannelSize(lobes));
      LafortuneChannelToArray(*p, c, x.data());
      std::vector<double> lut(n_views);
      for (size_t k = 0; k < n_views; ++k) lut[k] = (*t)[k][c];
      const JointChannelResult r = SolveJointChannel(
          on, own, c, lobes, options, max_t, peak_cap, x.data(), &lut);
      out.iterations += r.iterations;
      out.usable = out.usable && r.usable;
      out.converged = out.converged && r.converged;
      if (!r.usable) continue;
      LafortuneChannelFromArray(x.data(), c, p);
      for (size_t k = 0; k < n_views; ++k) (*t)[k][c] = lut[k];
    }
    FollowOwnedViews(own, on.views, t);
  }
  return out;
}

void NormaliseLookupTable(const std::vector<bool>& own, double peak_cap,
                          LafortuneParams* p, std::vector<glm::dvec3>* t) {
  for (int c = 0; c < 3; ++c) {
    double mean = 0.0;
    int owned = 0;
    for (size_t k = 0; k < t->size(); ++k) {
      if (!own[k]) continue;
      mean += (*t)[k][c];
      ++owned;
    }
    if (owned == 0) return;
    mean /= owned;
    if (!(mean > 0.0) || !std::isfinite(mean)) continue;
    LafortuneParams scaled = *p;
    scaled.diffuse[c] *= mean;
    for (LafortuneLobe& lobe : scaled.lobes) {
      const double f = std::pow(mean, 1.0 / lobe.n[c]);
      for (glm::dvec3* field : {&lobe.cx, &lobe.cy, &lobe.cz}) (*field)[c] *= f;
    }
    if (!LobesWithinReach(scaled, peak_cap) ||
        scaled.diffuse[c] > kLafortuneDiffuse.fit_hi) {
      continue;
    }
    *p = scaled;
    for (glm::dvec3& v : *t) v[c] /= mean;
  }
}

LafortuneFitResult FitLafortune(const TexelSamples& samples,
                                const LafortuneFitOptions& options) {
  LafortuneFitResult joint = FitLafortuneOnce(samples, options);
  const bool plausible =
      joint.report.usable && !(joint.report.energy_scale < 1.0);
  // Only where the joint solve ran (a fit reports its fitted views).
  if (plausible ||
      !JointSolveRuns(options, joint.report.lut_views_fitted > 0)) {
    return joint;
  }
  // The joint optimum is not plausible: its T grew where the lobes do not
  // reach, and the table's interpolation carries it to directions they do
  // (docs/lafortune.md). The paper's alternation, which keeps T near its
  // start, from the same start; it is kept when it is less scaled.
  LafortuneFitOptions alternate = options;
  alternate.solve = LafortuneSolve::kAlternate;
  LafortuneFitResult r = FitLafortuneOnce(samples, alternate);
  r.report.iterations += joint.report.iterations;
  if (!r.report.usable ||
      (joint.report.usable &&
       !(r.report.energy_scale > joint.report.energy_scale))) {
    joint.report.iterations = r.report.iterations;
    return joint;
  }
  char why[120];
  std::snprintf(why, sizeof(why),
                "the joint solve's optimum reflected %.3g times what it "
                "received; ",
                joint.report.usable ? 1.0 / joint.report.energy_scale : 0.0);
  r.report.termination =
      (joint.report.usable ? why : "the joint solve failed; ") +
      std::string("alternation: ") + r.report.termination;
  r.report.solve_fallback = true;
  return r;
}

}  // namespace clothfit
