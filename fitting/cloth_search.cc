#include "fitting/cloth_search.h"

#include <algorithm>
#include <cmath>

#include "fitting/start_search.h"

namespace clothfit {
namespace {

// The radical inverse of i in base b: the Halton sequence's coordinate
// (Halton 1960), low-discrepancy in each dimension with one prime per
// dimension.
double RadicalInverse(int i, int b) {
  double f = 1.0, r = 0.0;
  for (; i > 0; i /= b) {
    f /= b;
    r += f * (i % b);
  }
  return r;
}

constexpr int kPrimes[] = {2,  3,  5,  7,  11, 13, 17, 19, 23, 29, 31,
                           37, 41, 43, 47, 53, 59, 61, 67, 71, 73, 79};

// A free entry of the geometry (or eta) and the range the design covers.
struct DesignEntry {
  size_t index;
  double lo, hi;
};

std::vector<DesignEntry> DesignEntries(const ClothStartProblem& problem) {
  const ClothVector& v = problem.weave->vector;
  const std::vector<ParameterSpec>& specs = *problem.specs;
  std::vector<DesignEntry> out;
  auto add = [&](size_t i, double lo, double hi) {
    if (!specs[i].free) return;
    lo = std::max(lo, specs[i].lower);
    hi = std::min(hi, specs[i].upper);
    if (hi > lo) out.push_back({i, lo, hi});
  };
  // A rotation by 180 degrees turns each thread around; with symmetric
  // offsets it is the same weave, so half a turn covers the orientations.
  add(v.Rotation(), -90.0, 90.0);
  for (size_t j = 0; j < v.Threads(); ++j) {
    // eta: from its search limit 1.01 (a Fresnel term that acts toward
    // grazing only) to fibres' 1.46-1.6.
    add(v.Thread(j), 1.01, 1.6);
    add(v.Coverage(j), 0.0, 1.0);  // a stick entry
    add(v.OffsetScale(j), 0.0, 3.0);
    for (size_t k = 0; k < v.Offsets(j); ++k) add(v.Offset(j, k), -80.0, 80.0);
  }
  return out;
}

// The starts of one geometry: x's widths and linear entries searched.
std::vector<StartPoint> SearchGeometry(const ClothStartProblem& problem,
                                       const std::vector<double>& x, int keep) {
  const MeasurementTable& table = *problem.table;
  const Weave& weave = *problem.weave;
  const ClothVector& v = weave.vector;
  const std::vector<ParameterSpec>& specs = *problem.specs;
  const ClothParams cloth = ClothFromVector(weave, ReportedVector(weave, x));
  const size_t n = cloth.threads.size();
  const size_t rows = table.rows.size();
  // Tangent samples (with their Fresnel terms) and 1 / Q of every row
  // (times its factor).
  const std::vector<bool> eta_fixed(n, true);
  std::vector<RowSamples> samples(rows);
  std::vector<double> inv_q(rows, 0.0);
  for (size_t i = 0; i < rows; ++i) {
    samples[i] = ComputeRowSamples(cloth, eta_fixed, table.rows[i]);
    ClothNormalisation<double> normalisation;
    for (size_t j = 0; j < n; ++j) {
      Vec3<double> s_j;
      double w_j;
      ThreadSums(cloth.threads[j].params, samples[i], j, &s_j, &w_j);
      normalisation.Add(cloth.threads[j].coverage, w_j);
    }
    const double q = normalisation.Q(table.rows[i].wi.z);
    inv_q[i] = q > 0.0 ? 1.0 / q : 0.0;
    if (!problem.row_factor.empty()) inv_q[i] *= problem.row_factor[i];
  }
  StartSearchProblem search;
  search.table = &table;
  search.weighting = problem.weighting;
  search.contribution = [&](size_t j, const ThreadParams& p) {
    RowValues values(rows);
    const double coverage = cloth.threads[j].coverage;
    for (size_t i = 0; i < rows; ++i) {
      Vec3<double> s_j;
      double w_j;
      ThreadSums(p, samples[i], j, &s_j, &w_j);
      values[i] = ConvertQuantity(s_j * (coverage * inv_q[i]),
                                  Quantity::kCosineWeighted, table.quantity,
                                  table.rows[i].wi.z);
    }
    return values;
  };
  search.shared_albedo = weave.shared_albedo;
  search.fit_scale = specs[v.Scale()].free;
  auto free = [&](size_t i) { return specs[i].free; };
  for (size_t j = 0; j < n; ++j) {
    const size_t t = v.Thread(j);
    search.init.push_back(cloth.threads[j].params);
    search.kd_free.push_back(free(t + 1));
    search.gamma_s_free.push_back(problem.search_widths && free(t + 2));
    search.gamma_v_free.push_back(problem.search_widths && free(t + 3));
    // A shared albedo is thread 0's (the others' entries are fixed).
    const size_t owner = weave.shared_albedo ? v.Thread(0) : t;
    search.albedo_free.push_back(free(owner + 4) || free(owner + 5) ||
                                 free(owner + 6));
  }
  const bool diffuse_free = free(v.Diffuse(0));
  if (diffuse_free || cloth.diffuse != glm::dvec3(0.0)) {
    search.diffuse_basis.resize(rows);
    for (size_t i = 0; i < rows; ++i) {
      const double z = table.rows[i].wi.z;
      search.diffuse_basis[i] =
          IsReflectionRow(table.rows[i])
              ? ConvertQuantity(glm::dvec3(z / kPi), Quantity::kCosineWeighted,
                                table.quantity, z)
              : glm::dvec3(0.0);
      if (!problem.row_factor.empty()) {
        search.diffuse_basis[i] *= problem.row_factor[i];
      }
    }
    search.diffuse_free = diffuse_free;
    search.init_diffuse = cloth.diffuse;
  }
  return SearchStarts(search, keep);
}

}  // namespace

ClothStarts SearchClothStarts(const ClothStartProblem& problem, int keep) {
  const ClothVector& v = problem.weave->vector;
  const std::vector<DesignEntry> design = DesignEntries(problem);
  const int points = design.empty() ? 0 : std::max(0, problem.design_points);
  struct Candidate {
    double cost;
    std::vector<double> x;
  };
  std::vector<Candidate> candidates;
  for (int p = 0; p <= points; ++p) {
    std::vector<double> x = problem.init;
    for (size_t d = 0; d < design.size() && p > 0; ++d) {
      const double u =
          RadicalInverse(p, kPrimes[d % (sizeof(kPrimes) / sizeof(int))]);
      x[design[d].index] = design[d].lo + u * (design[d].hi - design[d].lo);
    }
    // The init's geometry may give several starts; each other point one.
    for (const StartPoint& point :
         SearchGeometry(problem, x, p == 0 ? keep : 1)) {
      std::vector<double> start = x;
      for (size_t j = 0; j < point.threads.size(); ++j) {
        double t[kThreadFlatSize];
        ToArray(point.threads[j], t);
        std::copy(t, t + kThreadFlatSize, start.begin() + v.Thread(j));
      }
      for (int c = 0; c < 3; ++c) start[v.Diffuse(c)] = point.diffuse[c];
      start[v.Scale()] = point.scale;
      candidates.push_back({point.cost, start});
    }
  }
  std::stable_sort(
      candidates.begin(), candidates.end(),
      [](const Candidate& a, const Candidate& b) { return a.cost < b.cost; });
  ClothStarts out;
  out.design_points = points + 1;
  for (size_t k = 0; k < candidates.size() && static_cast<int>(k) < keep; ++k) {
    out.starts.push_back(candidates[k].x);
  }
  return out;
}

}  // namespace clothfit
