#include "fitting/start_search.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <stdexcept>

#include "fitting/least_squares.h"
#include "fitting/residual_weight.h"
#include "fitting/small_least_squares.h"
#include "models/microcylinder_cloth.h"

namespace clothfit {
namespace {

// Widths a factor sqrt(2) apart from 1 to 90 degrees, and the initial one;
// only the initial one when the width is fixed.
std::vector<double> WidthGrid(bool free, double init) {
  if (!free) return {init};
  std::vector<double> values = {init};
  for (double w = 1.0; w <= 90.0; w *= std::sqrt(2.0)) values.push_back(w);
  std::sort(values.begin(), values.end());
  values.erase(std::unique(values.begin(), values.end()), values.end());
  return values;
}

// The basis vectors over the table, and their weighted inner products per
// channel: G_c(u, v) = sum_i w_ic B_u[i][c] B_v[i][c], b_c(u) = sum_i w_ic
// B_u[i][c] y_ic, yy_c = sum_i w_ic y_ic^2. Every least-squares problem of
// the search is then assembled from these sums, independent of the rows.
class Gram {
 public:
  Gram(const MeasurementTable& table, const Weighting& weighting,
       const std::vector<RowValues>& vectors)
      : n_(vectors.size()), channels_(table.channels) {
    g_.assign(channels_ * n_ * n_, 0.0);
    b_.assign(channels_ * n_, 0.0);
    yy_.assign(channels_, 0.0);
    std::vector<double> column(n_);
    for (size_t i = 0; i < table.rows.size(); ++i) {
      const TableRow& row = table.rows[i];
      const glm::dvec3 weight = weighting.InverseVariance(row, 1.0);
      for (int c = 0; c < channels_; ++c) {
        const double w = weight[c];
        const double y = row.value[c];
        for (size_t u = 0; u < n_; ++u) column[u] = vectors[u][i][c];
        double* g = &g_[c * n_ * n_];
        for (size_t u = 0; u < n_; ++u) {
          const double wu = w * column[u];
          if (wu == 0.0) continue;
          for (size_t v = u; v < n_; ++v) g[u * n_ + v] += wu * column[v];
          b_[c * n_ + u] += wu * y;
        }
        yy_[c] += w * y * y;
      }
    }
    for (int c = 0; c < channels_; ++c) {  // mirror the upper triangle
      double* g = &g_[c * n_ * n_];
      for (size_t u = 0; u < n_; ++u) {
        for (size_t v = 0; v < u; ++v) g[u * n_ + v] = g[v * n_ + u];
      }
    }
  }
  double G(int c, size_t u, size_t v) const {
    return g_[(c * n_ + u) * n_ + v];
  }
  double B(int c, size_t u) const { return b_[c * n_ + u]; }
  double YY(int c) const { return yy_[c]; }

 private:
  size_t n_;
  int channels_;
  std::vector<double> g_, b_, yy_;
};

// The most threads a search handles (a cloth has 1 to 3), and so the most
// linear entries of one problem: an albedo and a B per thread, the
// diffuse amplitude and the scale.
constexpr size_t kMaxThreads = 3;
constexpr int kMaxLinear = 2 * kMaxThreads + 2;
static_assert(kMaxLinear <= kMaxSmallSystem, "see small_least_squares.h");

// A linear combination of basis vectors: at most three per thread (its
// surface, P and R) and the diffuse one.
struct Combination {
  static constexpr int kMaxTerms = 3 * kMaxThreads + 1;
  size_t index[kMaxTerms];
  double weight[kMaxTerms];
  int size = 0;
  void Add(size_t i, double w) {
    index[size] = i;
    weight[size] = w;
    ++size;
  }
};

double Dot(const Gram& gram, int c, const Combination& a,
           const Combination& b) {
  double sum = 0.0;
  for (int u = 0; u < a.size; ++u) {
    for (int v = 0; v < b.size; ++v) {
      sum += a.weight[u] * b.weight[v] * gram.G(c, a.index[u], b.index[v]);
    }
  }
  return sum;
}

double DotY(const Gram& gram, int c, const Combination& a) {
  double sum = 0.0;
  for (int u = 0; u < a.size; ++u) sum += a.weight[u] * gram.B(c, a.index[u]);
  return sum;
}

// Basis vectors of one thread: surface(gamma_s) per width of its grid,
// P(gamma_v) per width, and R (see start_search.h).
struct ThreadVectors {
  std::vector<double> gamma_s, gamma_v;
  std::vector<size_t> surface, p;  // indices into the basis
  size_t r = 0;
};

class Search {
 public:
  explicit Search(const StartSearchProblem& problem) : problem_(problem) {
    const size_t n = problem.init.size();
    if (n > kMaxThreads) {
      throw std::invalid_argument("start search: more than 3 threads");
    }
    std::vector<RowValues> vectors;
    auto add = [&](RowValues v) {
      vectors.push_back(std::move(v));
      return vectors.size() - 1;
    };
    threads_.resize(n);
    for (size_t j = 0; j < n; ++j) {
      const ThreadParams& init = problem.init[j];
      ThreadVectors& t = threads_[j];
      t.gamma_s = WidthGrid(problem.gamma_s_free[j], init.gamma_s_deg);
      t.gamma_v = WidthGrid(problem.gamma_v_free[j], init.gamma_v_deg);
      ThreadParams p = init;
      p.albedo = glm::dvec3(0.0);
      for (double gs : t.gamma_s) {
        p.gamma_s_deg = gs;
        t.surface.push_back(add(problem.contribution(j, p)));
      }
      // The volume term does not depend on gamma_s: subtract the surface
      // at the initial width from evaluations with unit albedo.
      p.gamma_s_deg = init.gamma_s_deg;
      const RowValues surface = problem.contribution(j, p);
      auto minus_surface = [&](RowValues v) {
        for (size_t i = 0; i < v.size(); ++i) v[i] -= surface[i];
        return v;
      };
      p.albedo = glm::dvec3(1.0);
      p.kd = 0.0;
      for (double gv : t.gamma_v) {
        p.gamma_v_deg = gv;
        t.p.push_back(add(minus_surface(problem.contribution(j, p))));
      }
      p.kd = 1.0;
      t.r = add(minus_surface(problem.contribution(j, p)));
    }
    if (!problem.diffuse_basis.empty()) diffuse_ = add(problem.diffuse_basis);
    gram_ = std::make_unique<Gram>(*problem.table, *problem.weighting, vectors);
  }

  const ThreadVectors& Thread(size_t j) const { return threads_[j]; }

  // Solves the linear parameters for one grid index pair (gamma_s index,
  // gamma_v index) per thread; fills *point and returns its cost.
  double Evaluate(const std::vector<std::pair<int, int>>& choice,
                  StartPoint* point) const {
    const StartSearchProblem& problem = problem_;
    const int channels = problem.table->channels;
    const size_t n = choice.size();  // <= kMaxThreads (the constructor)
    // Columns of the design: albedos (shared or per thread with a free
    // albedo), B_j = A_j kd_j for threads with kd free, then the scale; the
    // constant part holds the surfaces and the volumes of fixed albedos.
    // The volume A P + B (R - P) is U P + B R with U = A - B: the bounds
    // A >= 0, 0 <= B <= A are then U >= 0, B >= 0, bounds of each entry
    // alone, unless threads share one albedo (several B_j <= A).
    int a_index[kMaxThreads], b_index[kMaxThreads];
    int m = 0, shared_index = -1;
    for (size_t j = 0; j < n; ++j) {
      a_index[j] = b_index[j] = -1;
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
    const bool diffuse = diffuse_ != kNone;
    const int d_index = diffuse && problem.diffuse_free ? m++ : -1;
    const int s_index = problem.fit_scale ? m++ : -1;
    const bool split = !problem.shared_albedo;  // columns U and B
    // The bounds: s >= 1e-6, the others >= 0 (and 0 <= B_j <= A_j).
    auto lower = [&](int a) { return a == s_index ? 1e-6 : 0.0; };
    auto upper = [&](int a, const double* x) {
      double hi = 1e6;
      for (size_t j = 0; j < n && !split; ++j) {
        if (b_index[j] == a) hi = x[a_index[j]];
      }
      return std::max(lower(a), hi);
    };

    point->threads = problem.init;
    point->scale = 1.0;
    point->diffuse = problem.init_diffuse;
    glm::dvec3 a_out[kMaxThreads] = {}, b_out[kMaxThreads] = {};
    double scale_sum = 0.0;
    for (int c = 0; c < channels; ++c) {
      Combination column[kMaxLinear];
      Combination constant;
      for (size_t j = 0; j < n; ++j) {
        const ThreadVectors& t = threads_[j];
        const size_t surface = t.surface[choice[j].first];
        const size_t p = t.p[choice[j].second];
        constant.Add(surface, 1.0);
        const double kd = problem.init[j].kd;
        if (a_index[j] < 0) {  // fixed albedo: a known volume
          const double a = problem.init[j].albedo[c];
          constant.Add(p, a * (1.0 - kd));
          constant.Add(t.r, a * kd);
        } else if (b_index[j] < 0) {  // fixed kd
          column[a_index[j]].Add(p, 1.0 - kd);
          column[a_index[j]].Add(t.r, kd);
        } else if (split) {
          column[a_index[j]].Add(p, 1.0);
          column[b_index[j]].Add(t.r, 1.0);
        } else {
          column[a_index[j]].Add(p, 1.0);
          column[b_index[j]].Add(t.r, 1.0);
          column[b_index[j]].Add(p, -1.0);
        }
      }
      if (d_index >= 0) {
        column[d_index].Add(diffuse_, 1.0);
      } else if (diffuse) {
        constant.Add(diffuse_, problem.init_diffuse[c]);
      }
      if (s_index >= 0) column[s_index] = constant;
      double ata[kMaxLinear * kMaxLinear], atb[kMaxLinear];
      for (int a = 0; a < m; ++a) {
        atb[a] = DotY(*gram_, c, column[a]);
        if (s_index < 0) atb[a] -= Dot(*gram_, c, column[a], constant);
        for (int b = 0; b <= a; ++b) {
          ata[a * m + b] = ata[b * m + a] =
              Dot(*gram_, c, column[a], column[b]);
        }
      }
      // The unconstrained solution is the bounded one where it lies within
      // the bounds (the problem is convex); else, with bounds on each
      // entry alone, the active-set solution, and otherwise projected
      // Gauss-Seidel until a sweep no longer moves x.
      double x[kMaxLinear], lo[kMaxLinear];
      for (int a = 0; a < m; ++a) lo[a] = lower(a);
      bool inside = SolveCholesky(ata, atb, m, x);
      for (int a = 0; a < m && inside; ++a) {
        inside = x[a] >= lo[a] && x[a] <= upper(a, x);
      }
      if (!inside && split) {
        inside = SolveAboveBounds(ata, atb, lo, m, x);
        for (int a = 0; a < m && inside; ++a) inside = x[a] <= upper(a, x);
      }
      if (!inside) {
        std::fill(x, x + m, 0.0);
        if (s_index >= 0) x[s_index] = 1.0;
        for (int sweep = 0; sweep < 200; ++sweep) {
          double change = 0.0;
          for (int a = 0; a < m; ++a) {
            if (!(ata[a * m + a] > 0.0)) continue;
            double rhs = atb[a];
            for (int b = 0; b < m; ++b) {
              if (b != a) rhs -= ata[a * m + b] * x[b];
            }
            const double next =
                std::clamp(rhs / ata[a * m + a], lower(a), upper(a, x));
            change = std::max(
                change, std::abs(next - x[a]) / std::max(1.0, std::abs(next)));
            x[a] = next;
          }
          if (change <= 1e-14) break;
        }
      }
      const double s = s_index >= 0 ? x[s_index] : 1.0;
      scale_sum += s;
      for (size_t j = 0; j < n; ++j) {
        if (a_index[j] >= 0) a_out[j][c] = x[a_index[j]] / s;
        if (b_index[j] >= 0) b_out[j][c] = x[b_index[j]] / s;
        if (split && b_index[j] >= 0) a_out[j][c] += b_out[j][c];  // U + B
      }
      if (d_index >= 0) {  // one channel: g and b follow r
        for (int k = c; k < (channels == 1 ? 3 : c + 1); ++k) {
          point->diffuse[k] = std::min(x[d_index] / s, kClothDiffuse.fit_hi);
        }
      }
    }
    if (s_index >= 0) point->scale = scale_sum / channels;
    for (size_t j = 0; j < n; ++j) {
      ThreadParams& tp = point->threads[j];
      tp.gamma_s_deg = threads_[j].gamma_s[choice[j].first];
      tp.gamma_v_deg = threads_[j].gamma_v[choice[j].second];
      if (a_index[j] < 0) continue;
      for (int c = 0; c < 3; ++c) {
        tp.albedo[c] =
            std::min(a_out[j][std::min(c, channels - 1)], kThreadAlbedo.fit_hi);
      }
      if (b_index[j] >= 0) {  // one kd for all channels
        double a = 0.0, b = 0.0;
        for (int c = 0; c < channels; ++c) {
          a += a_out[j][c];
          b += b_out[j][c];
        }
        tp.kd = a > 0.0 ? std::clamp(b / a, 0.0, 1.0) : tp.kd;
      }
    }
    // The exact cost of these parameters: |s model - y|^2 from the sums.
    double cost = 0.0;
    for (int c = 0; c < channels; ++c) {
      Combination model;
      for (size_t j = 0; j < n; ++j) {
        const ThreadParams& tp = point->threads[j];
        const ThreadVectors& t = threads_[j];
        model.Add(t.surface[choice[j].first], point->scale);
        model.Add(t.p[choice[j].second],
                  point->scale * tp.albedo[c] * (1.0 - tp.kd));
        model.Add(t.r, point->scale * tp.albedo[c] * tp.kd);
      }
      if (diffuse) model.Add(diffuse_, point->scale * point->diffuse[c]);
      cost += Dot(*gram_, c, model, model) - 2.0 * DotY(*gram_, c, model) +
              gram_->YY(c);
    }
    point->cost = std::isfinite(cost) ? std::max(cost, 0.0) : HUGE_VAL;
    return point->cost;
  }

 private:
  static constexpr size_t kNone = static_cast<size_t>(-1);
  const StartSearchProblem& problem_;
  std::vector<ThreadVectors> threads_;
  size_t diffuse_ = kNone;  // the Lambertian basis vector, if any
  std::unique_ptr<Gram> gram_;
};

}  // namespace

std::vector<StartPoint> SearchStarts(const StartSearchProblem& problem,
                                     int keep) {
  const size_t n = problem.init.size();
  const Search search(problem);
  // Start at each thread's initial widths (in its grid by construction).
  std::vector<std::pair<int, int>> current(n);
  for (size_t j = 0; j < n; ++j) {
    const ThreadVectors& t = search.Thread(j);
    const ThreadParams& p = problem.init[j];
    current[j].first = static_cast<int>(
        std::find(t.gamma_s.begin(), t.gamma_s.end(), p.gamma_s_deg) -
        t.gamma_s.begin());
    current[j].second = static_cast<int>(
        std::find(t.gamma_v.begin(), t.gamma_v.end(), p.gamma_v_deg) -
        t.gamma_v.begin());
  }
  // Coordinate descent over the threads: each thread's best grid point
  // with the others held, until nothing changes. Every evaluated point is
  // kept; the starts are chosen among them.
  std::map<std::vector<std::pair<int, int>>, StartPoint> seen;
  auto evaluate = [&](const std::vector<std::pair<int, int>>& c) {
    auto it = seen.find(c);
    if (it != seen.end()) return it->second.cost;
    StartPoint point;
    search.Evaluate(c, &point);
    return seen.emplace(c, point).first->second.cost;
  };
  double best = evaluate(current);
  for (int round = 0; round < 8; ++round) {
    bool changed = false;
    for (size_t j = 0; j < n; ++j) {
      const ThreadVectors& t = search.Thread(j);
      for (int a = 0; a < static_cast<int>(t.gamma_s.size()); ++a) {
        for (int b = 0; b < static_cast<int>(t.gamma_v.size()); ++b) {
          std::vector<std::pair<int, int>> trial = current;
          trial[j] = {a, b};
          const double cost = evaluate(trial);
          if (cost < best) {
            best = cost;
            current = trial;
            changed = true;
          }
        }
      }
    }
    if (!changed) break;
  }
  std::vector<StartPoint> all;
  for (auto& [key, point] : seen) all.push_back(point);
  std::sort(
      all.begin(), all.end(),
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

const MeasurementTable& SearchTable(const MeasurementTable& table,
                                    MeasurementTable* storage) {
  if (table.rows.size() <= kSampleRows) return table;
  storage->source = table.source;
  storage->metadata = table.metadata;
  storage->quantity = table.quantity;
  storage->channels = table.channels;
  storage->direction_columns = table.direction_columns;
  storage->has_sigma = table.has_sigma;
  storage->has_weight = table.has_weight;
  storage->has_texels = table.has_texels;
  storage->has_alpha = table.has_alpha;
  storage->has_normal = table.has_normal;
  storage->rows.clear();
  for (uint32_t i : SampleRows(table.rows.size(), kSampleRows)) {
    storage->rows.push_back(table.rows[i]);
  }
  return *storage;
}

std::vector<double> SearchRowValues(size_t rows,
                                    const std::vector<double>* per_row) {
  if (!per_row) return {};
  if (rows <= kSampleRows) return *per_row;
  std::vector<double> out;
  for (uint32_t i : SampleRows(rows, kSampleRows)) out.push_back((*per_row)[i]);
  return out;
}

}  // namespace clothfit
