#include "fitting/start_search.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

namespace clothfit {
namespace {

std::vector<double> Grid(bool free, double init, std::vector<double> values) {
  if (!free) return {init};
  values.push_back(init);
  std::sort(values.begin(), values.end());
  values.erase(std::unique(values.begin(), values.end()), values.end());
  return values;
}

// One grid point of one thread.
struct Choice {
  double eta, gamma_s, gamma_v;
  bool operator<(const Choice& o) const {
    return std::tie(eta, gamma_s, gamma_v) <
           std::tie(o.eta, o.gamma_s, o.gamma_v);
  }
  bool operator==(const Choice& o) const {
    return eta == o.eta && gamma_s == o.gamma_s && gamma_v == o.gamma_v;
  }
};

// Basis vectors of one thread, cached per (eta, width).
class ThreadBasis {
 public:
  ThreadBasis(const StartSearchProblem& problem, size_t j)
      : problem_(problem), j_(j) {}

  const RowValues& Surface(double eta, double gamma_s) {
    auto key = std::make_pair(eta, gamma_s);
    auto it = surface_.find(key);
    if (it != surface_.end()) return it->second;
    ThreadParams p = Base(eta);
    p.gamma_s_deg = gamma_s;
    p.albedo = glm::dvec3(0.0);
    return surface_[key] = problem_.contribution(j_, p);
  }
  // P(gamma_v) = c(A = 1, kd = 0) - surface, at the reference gamma_s.
  const RowValues& P(double eta, double gamma_v) {
    auto key = std::make_pair(eta, gamma_v);
    auto it = p_.find(key);
    if (it != p_.end()) return it->second;
    ThreadParams p = Base(eta);
    p.gamma_v_deg = gamma_v;
    p.kd = 0.0;
    p.albedo = glm::dvec3(1.0);
    return p_[key] = Minus(problem_.contribution(j_, p),
                           Surface(eta, p.gamma_s_deg));
  }
  // R = c(A = 1, kd = 1) - surface.
  const RowValues& R(double eta) {
    auto it = r_.find(eta);
    if (it != r_.end()) return it->second;
    ThreadParams p = Base(eta);
    p.kd = 1.0;
    p.albedo = glm::dvec3(1.0);
    return r_[eta] =
               Minus(problem_.contribution(j_, p), Surface(eta, p.gamma_s_deg));
  }
  // The volume term with the thread's fixed kd and unit albedo.
  RowValues FixedKdVolume(double eta, double gamma_v) {
    const double kd = problem_.init[j_].kd;
    const RowValues& p = P(eta, gamma_v);
    const RowValues& r = R(eta);
    RowValues out(p.size());
    for (size_t i = 0; i < p.size(); ++i) out[i] = (1.0 - kd) * p[i] + kd * r[i];
    return out;
  }

 private:
  ThreadParams Base(double eta) const {
    ThreadParams p = problem_.init[j_];
    p.eta = eta;
    return p;
  }
  static RowValues Minus(RowValues a, const RowValues& b) {
    for (size_t i = 0; i < a.size(); ++i) a[i] -= b[i];
    return a;
  }

  const StartSearchProblem& problem_;
  size_t j_;
  std::map<std::pair<double, double>, RowValues> surface_, p_;
  std::map<double, RowValues> r_;
};

// Solves the linear parameters for one choice per thread; returns the cost
// and fills *point.
double SolveLinear(const StartSearchProblem& problem,
                   std::vector<ThreadBasis>& bases,
                   const std::vector<Choice>& choice, StartPoint* point) {
  const MeasurementTable& table = *problem.table;
  const size_t n = choice.size();
  const size_t rows = table.rows.size();
  // Constant part (surfaces, and volumes of threads with fixed albedo).
  RowValues constant(rows, glm::dvec3(0.0));
  std::vector<const RowValues*> p(n, nullptr), r(n, nullptr);
  std::vector<RowValues> fixed_kd(n);
  for (size_t j = 0; j < n; ++j) {
    const Choice& c = choice[j];
    const RowValues& surface = bases[j].Surface(c.eta, c.gamma_s);
    for (size_t i = 0; i < rows; ++i) constant[i] += surface[i];
    if (problem.kd_free[j] && problem.albedo_free[j]) {
      p[j] = &bases[j].P(c.eta, c.gamma_v);
      r[j] = &bases[j].R(c.eta);
    } else {
      fixed_kd[j] = bases[j].FixedKdVolume(c.eta, c.gamma_v);
      p[j] = &fixed_kd[j];
      if (!problem.albedo_free[j]) {
        const glm::dvec3 a = problem.init[j].albedo;
        for (size_t i = 0; i < rows; ++i) constant[i] += a * fixed_kd[j][i];
      }
    }
  }
  // Unknowns per channel: albedos (one shared, or one per thread with a free
  // albedo), B_j for threads with kd free, then the scale.
  std::vector<int> a_index(n, -1), b_index(n, -1);
  int m = 0;
  int shared_index = -1;
  for (size_t j = 0; j < n; ++j) {
    if (!problem.albedo_free[j]) continue;
    if (problem.shared_albedo) {
      if (shared_index < 0) shared_index = m++;
      a_index[j] = shared_index;
    } else {
      a_index[j] = m++;
    }
  }
  for (size_t j = 0; j < n; ++j) {
    if (a_index[j] >= 0 && problem.kd_free[j]) b_index[j] = m++;
  }
  const int s_index = problem.fit_scale ? m++ : -1;

  point->threads = problem.init;
  std::vector<glm::dvec3> a_out(n, glm::dvec3(0.0)), b_out(n, glm::dvec3(0.0));
  double scale_sum = 0.0;
  for (int ch = 0; ch < table.channels; ++ch) {
    std::vector<double> ata(m * m, 0.0), atb(m, 0.0), basis(m);
    for (size_t i = 0; i < rows; ++i) {
      const TableRow& row = table.rows[i];
      const double w = row.weight / (row.sigma[ch] * row.sigma[ch]);
      std::fill(basis.begin(), basis.end(), 0.0);
      for (size_t j = 0; j < n; ++j) {
        if (a_index[j] >= 0) basis[a_index[j]] += (*p[j])[i][ch];
        if (b_index[j] >= 0) basis[b_index[j]] = (*r[j])[i][ch] - (*p[j])[i][ch];
      }
      double target = row.value[ch];
      if (s_index >= 0) {
        basis[s_index] = constant[i][ch];
      } else {
        target -= constant[i][ch];
      }
      for (int a = 0; a < m; ++a) {
        atb[a] += w * basis[a] * target;
        for (int b = 0; b < m; ++b) ata[a * m + b] += w * basis[a] * basis[b];
      }
    }
    std::vector<double> x(m, 0.0);
    if (s_index >= 0) x[s_index] = 1.0;
    for (int sweep = 0; sweep < 200; ++sweep) {  // projected Gauss-Seidel
      for (int a = 0; a < m; ++a) {
        if (!(ata[a * m + a] > 0.0)) continue;
        double rhs = atb[a];
        for (int b = 0; b < m; ++b) {
          if (b != a) rhs -= ata[a * m + b] * x[b];
        }
        double lo = a == s_index ? 1e-6 : 0.0, hi = 1e6;
        for (size_t j = 0; j < n; ++j) {
          if (b_index[j] == a) hi = x[a_index[j]];  // 0 <= B_j <= A_j
        }
        x[a] = std::clamp(rhs / ata[a * m + a], lo, std::max(lo, hi));
      }
    }
    const double s = s_index >= 0 ? x[s_index] : 1.0;
    scale_sum += s;
    for (size_t j = 0; j < n; ++j) {
      if (a_index[j] >= 0) a_out[j][ch] = x[a_index[j]] / s;
      if (b_index[j] >= 0) b_out[j][ch] = x[b_index[j]] / s;
    }
  }
  point->scale = s_index >= 0 ? scale_sum / table.channels : 1.0;
  for (size_t j = 0; j < n; ++j) {
    ThreadParams& tp = point->threads[j];
    tp.eta = choice[j].eta;
    tp.gamma_s_deg = choice[j].gamma_s;
    tp.gamma_v_deg = choice[j].gamma_v;
    if (a_index[j] < 0) continue;
    for (int ch = 0; ch < 3; ++ch) {
      tp.albedo[ch] = std::min(a_out[j][std::min(ch, table.channels - 1)], 1e3);
    }
    if (b_index[j] >= 0) {
      double a = 0.0, b = 0.0;
      for (int ch = 0; ch < table.channels; ++ch) {
        a += a_out[j][ch];
        b += b_out[j][ch];
      }
      tp.kd = a > 0.0 ? std::clamp(b / a, 0.0, 1.0) : tp.kd;
    }
  }
  // The exact cost of the resulting parameters (kd shared over channels).
  double cost = 0.0;
  for (size_t i = 0; i < rows; ++i) {
    glm::dvec3 model(0.0);
    for (size_t j = 0; j < n; ++j) {
      const ThreadParams& tp = point->threads[j];
      model += bases[j].Surface(tp.eta, tp.gamma_s_deg)[i];
      const glm::dvec3 pv = bases[j].P(tp.eta, tp.gamma_v_deg)[i];
      const glm::dvec3 rv = bases[j].R(tp.eta)[i];
      model += tp.albedo * ((1.0 - tp.kd) * pv + tp.kd * rv);
    }
    const TableRow& row = table.rows[i];
    for (int ch = 0; ch < table.channels; ++ch) {
      const double d = (point->scale * model[ch] - row.value[ch]) / row.sigma[ch];
      cost += row.weight * d * d;
    }
  }
  point->cost = std::isfinite(cost) ? cost : HUGE_VAL;
  return point->cost;
}

}  // namespace

std::vector<StartPoint> SearchStarts(const StartSearchProblem& problem,
                                     int keep) {
  const size_t n = problem.init.size();
  // Widths a factor sqrt(2) apart: narrow specular lobes need the finer step.
  std::vector<double> kWidths;
  for (double w = 1.0; w <= 90.0; w *= std::sqrt(2.0)) kWidths.push_back(w);
  std::vector<std::vector<Choice>> grids(n);
  std::vector<Choice> current(n);
  for (size_t j = 0; j < n; ++j) {
    const ThreadParams& p = problem.init[j];
    // eta: its initial value only. Its effect (Fresnel) is mild and smooth,
    // the solver refines it, and a grid over it tripled the search time.
    for (double eta : {p.eta}) {
      for (double gs : Grid(problem.gamma_s_free[j], p.gamma_s_deg, kWidths)) {
        for (double gv : Grid(problem.gamma_v_free[j], p.gamma_v_deg, kWidths)) {
          grids[j].push_back({eta, gs, gv});
        }
      }
    }
    current[j] = {p.eta, p.gamma_s_deg, p.gamma_v_deg};
  }
  std::vector<ThreadBasis> bases;
  for (size_t j = 0; j < n; ++j) bases.emplace_back(problem, j);

  // Coordinate descent over the threads; every evaluated point is kept.
  std::map<std::vector<Choice>, StartPoint> seen;
  auto evaluate = [&](const std::vector<Choice>& c) -> double {
    auto it = seen.find(c);
    if (it != seen.end()) return it->second.cost;
    StartPoint point;
    SolveLinear(problem, bases, c, &point);
    seen[c] = point;
    return point.cost;
  };
  double best = evaluate(current);
  for (int round = 0; round < 4; ++round) {
    bool changed = false;
    for (size_t j = 0; j < n; ++j) {
      for (const Choice& option : grids[j]) {
        std::vector<Choice> trial = current;
        trial[j] = option;
        const double cost = evaluate(trial);
        if (cost < best) {
          best = cost;
          current = trial;
          changed = true;
        }
      }
    }
    if (!changed) break;
  }
  std::vector<StartPoint> all;
  for (auto& [key, point] : seen) all.push_back(point);
  std::sort(all.begin(), all.end(),
            [](const StartPoint& a, const StartPoint& b) { return a.cost < b.cost; });
  // Keep the best, then the next best that differ from every kept one by a
  // factor of 2 or more in some width: neighbours on the grid lead the
  // solver into the same basin.
  auto distinct = [](const StartPoint& a, const StartPoint& b) {
    for (size_t j = 0; j < a.threads.size(); ++j) {
      const ThreadParams& p = a.threads[j];
      const ThreadParams& q = b.threads[j];
      if (std::abs(std::log2(p.gamma_s_deg / q.gamma_s_deg)) >= 0.99 ||
          std::abs(std::log2(p.gamma_v_deg / q.gamma_v_deg)) >= 0.99) {
        return true;
      }
    }
    return false;
  };
  std::vector<StartPoint> kept;
  for (const StartPoint& point : all) {
    if (static_cast<int>(kept.size()) >= keep) break;
    bool ok = true;
    for (const StartPoint& k : kept) ok = ok && distinct(point, k);
    if (ok) kept.push_back(point);
  }
  return kept;
}

}  // namespace clothfit
