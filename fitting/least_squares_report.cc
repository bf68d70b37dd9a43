// The report of a least-squares solution: covariance, standard
// deviations (by the delta method through a reparameterisation), the
// parameters at bounds or search limits (fitting/least_squares_internal.h).
#include <ceres/ceres.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <vector>

#include "fitting/covariance_internal.h"
#include "fitting/least_squares_internal.h"

namespace clothfit {
namespace {

// The free blocks of a built problem, for Evaluate.
std::vector<double*> FreeBlocks(const BuiltProblem& built) {
  std::vector<double*> free;
  for (double* block : built.blocks) {
    if (built.problem->HasParameterBlock(block) &&
        !built.problem->IsParameterBlockConstant(block)) {
      free.push_back(block);
    }
  }
  return free;
}

// The Jacobian (dense) and residuals of `built` over its free blocks.
void EvaluateDense(BuiltProblem* built, int threads, Eigen::MatrixXd* j,
                   Eigen::VectorXd* r) {
  ceres::Problem::EvaluateOptions eval;
  eval.parameter_blocks = FreeBlocks(*built);
  eval.num_threads = threads;
  ceres::CRSMatrix crs;
  std::vector<double> residuals;
  built->problem->Evaluate(eval, nullptr, &residuals, nullptr, &crs);
  *j = Eigen::MatrixXd::Zero(crs.num_rows, crs.num_cols);
  for (int row = 0; row < crs.num_rows; ++row) {
    for (int k = crs.rows[row]; k < crs.rows[row + 1]; ++k) {
      (*j)(row, crs.cols[k]) = crs.values[k];
    }
  }
  *r = Eigen::Map<const Eigen::VectorXd>(residuals.data(), residuals.size());
}

// The standard deviations of lsq.reported(x) by the delta method:
// G Cov G^T over the free entries, G by central differences (steps of
// 1e-6 of the entry's scale; the reparameterisations are smooth beyond
// their bounds too).
void ReportedStddev(const LeastSquaresProblem& lsq,
                    const std::vector<double>& x,
                    const std::vector<int>& free_index,
                    const ColumnCovariance& cov, std::vector<double>* stddev,
                    std::vector<double>* sandwich) {
  const int n = static_cast<int>(free_index.size());
  Eigen::MatrixXd g(n, n);
  for (int c = 0; c < n; ++c) {
    const double h = 1e-6 * std::max(1.0, std::abs(x[free_index[c]]));
    std::vector<double> up = x, down = x;
    up[free_index[c]] += h;
    down[free_index[c]] -= h;
    const std::vector<double> yu = lsq.reported(up), yd = lsq.reported(down);
    for (int r = 0; r < n; ++r) {
      g(r, c) = (yu[free_index[r]] - yd[free_index[r]]) / (2.0 * h);
    }
  }
  const Eigen::MatrixXd c_model = g * cov.covariance * g.transpose();
  const bool has_sandwich = cov.sandwich_covariance.rows() == n;
  Eigen::MatrixXd c_sandwich;
  if (has_sandwich) c_sandwich = g * cov.sandwich_covariance * g.transpose();
  for (int r = 0; r < n; ++r) {
    (*stddev)[free_index[r]] = std::sqrt(std::max(0.0, c_model(r, r)));
    (*sandwich)[free_index[r]] =
        has_sandwich ? std::sqrt(std::max(0.0, c_sandwich(r, r))) : -1.0;
  }
}

}  // namespace

void Report(const LeastSquaresProblem& lsq, const SolverOptions& options,
            const std::vector<double>& x, BuiltProblem* built,
            FitReport* report) {
  ceres::Problem::EvaluateOptions eval;
  eval.parameter_blocks = FreeBlocks(*built);
  // Free entries in the Jacobian's column order (blocks in order; a
  // SubsetManifold's tangent space keeps the free entries in order).
  std::vector<int> free_index;
  {
    int offset = 0;
    for (size_t b = 0; b < lsq.block_sizes.size(); ++b) {
      const bool in_problem =
          std::find(eval.parameter_blocks.begin(), eval.parameter_blocks.end(),
                    built->blocks[b]) != eval.parameter_blocks.end();
      for (int i = 0; i < lsq.block_sizes[b]; ++i) {
        if (in_problem && lsq.specs[offset + i].free) {
          free_index.push_back(offset + i);
        }
      }
      offset += lsq.block_sizes[b];
    }
  }
  std::vector<double> stddev(x.size(), -1.0), sandwich(x.size(), -1.0);
  std::vector<bool> no_effect(x.size(), false);
  const int n = static_cast<int>(free_index.size());
  if (n > 0) {
    Eigen::MatrixXd j;
    Eigen::VectorXd r;
    EvaluateDense(built, Threads(options), &j, &r);
    // The rows' own Jacobian for the sandwich's leverages, in blocks of
    // rows (the solved problem's blocks are compressed).
    const RowBlockVisitor row_blocks = [&](const auto& visit) {
      constexpr size_t kBlock = 65536;
      const size_t rows = lsq.rows;
      std::vector<uint32_t> subset;
      for (size_t begin = 0; begin < rows; begin += kBlock) {
        subset.clear();
        for (size_t i = begin; i < std::min(rows, begin + kBlock); ++i) {
          subset.push_back(static_cast<uint32_t>(i));
        }
        BuiltProblem part;
        std::vector<double> xp = x;
        Build(lsq, options, &xp, &part, ResidualRows{&subset, false});
        Eigen::MatrixXd jb;
        Eigen::VectorXd rb;
        EvaluateDense(&part, Threads(options), &jb, &rb);
        visit(jb, rb);
      }
    };
    // Columns that are zero next to the others: entries that change no
    // residual at the solution (a thread of coverage 0, the volume width
    // at kd = 1).
    if (j.cols() == n && j.rows() > 0) {
      const Eigen::VectorXd norms = j.colwise().norm();
      const double largest = norms.maxCoeff();
      for (int c = 0; c < n; ++c) {
        no_effect[free_index[c]] = !(norms[c] > 1e-12 * largest);
      }
    }
    if (j.cols() != n) {
      report->identifiability = "not identifiable: internal column mismatch";
    } else {
      // Rows evaluated uncompressed (lsq.rows == 0, a robust loss) are
      // their own row blocks.
      const bool compressed = lsq.rows > 0 && built->loss == nullptr;
      const ColumnCovariance cov = CovarianceOfColumns(
          j, r, lsq.sigma_known, report->final_cost, report->residuals,
          compressed ? row_blocks : nullptr);
      for (int c = 0; c < n; ++c) {
        stddev[free_index[c]] = cov.stddev[c];
        sandwich[free_index[c]] = cov.sandwich[c];
      }
      if (lsq.reported && cov.covariance.rows() == n) {
        ReportedStddev(lsq, x, free_index, cov, &stddev, &sandwich);
        // An entry held for the others' covariance has none of its own.
        for (int c : cov.not_identifiable) {
          stddev[free_index[c]] = sandwich[free_index[c]] = -1.0;
        }
      }
      report->stddev_conditional = cov.conditional;
      if (!cov.not_identifiable.empty()) {
        report->identifiability = "not identifiable:";
        for (size_t k = 0; k < cov.not_identifiable.size(); ++k) {
          report->identifiability +=
              (k ? ", " : " ") +
              lsq.specs[free_index[cov.not_identifiable[k]]].name;
        }
      }
    }
  }
  const std::vector<double> values = lsq.reported ? lsq.reported(x) : x;
  for (size_t i = 0; i < x.size(); ++i) {
    const ParameterSpec& spec = lsq.specs[i];
    ParameterReport p;
    p.name = spec.name;
    p.value = values[i];
    p.free = spec.free;
    p.lower = spec.lower;
    p.upper = spec.upper;
    // On the solver's bound (a reparameterised entry's too).
    p.at_bound = spec.free && OnFitBound(x[i], spec.lower, spec.upper);
    const bool on_lower = x[i] - spec.lower < spec.upper - x[i];
    p.at_search_limit = p.at_bound && !spec.physical_bounds &&
                        !(on_lower ? spec.physical_lower : spec.physical_upper);
    p.no_effect = no_effect[i];
    p.stddev = stddev[i];
    p.stddev_sandwich = sandwich[i];
    report->parameters.push_back(p);
  }
}

}  // namespace clothfit
