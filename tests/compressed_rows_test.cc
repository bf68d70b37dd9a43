// A chunk of rows as one compressed residual block
// (fitting/compressed_rows.cc): the problem Ceres sees has the rows' cost,
// gradient and Gauss-Newton matrix J^T J, so a solve takes the same steps and
// ends at the same point.
#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <memory>
#include <vector>

#include "fitting/model_residual_internal.h"

namespace clothfit {
namespace {

// A nonlinear toy: value = a exp(-b x) + c x per channel, three channels
// scaled differently; blocks {a, b} and {c}.
struct ToyEvaluator {
  std::vector<double> x;
  template <typename T>
  Vec3<T> operator()(const T* const* blocks, size_t i) const {
    const T v = blocks[0][0] * exp(-blocks[0][1] * x[i]) + blocks[1][0] * x[i];
    return Vec3<T>(v, T(2.0) * v, v * v);
  }
};

struct Toy {
  MeasurementTable table;
  std::unique_ptr<Weighting> weighting;
  std::shared_ptr<ToyEvaluator> evaluator = std::make_shared<ToyEvaluator>();
  FitRows rows;
};

// n rows with values off the model at (1, 0.5, 0.1) by a deterministic
// wiggle.
std::unique_ptr<Toy> MakeToy(int n) {
  auto toy = std::make_unique<Toy>();
  toy->table.rows.resize(n);
  for (int i = 0; i < n; ++i) {
    const double x = 0.01 * i;
    toy->evaluator->x.push_back(x);
    const double v = exp(-0.5 * x) + 0.1 * x + 0.05 * std::sin(7.0 * i);
    toy->table.rows[i].value = glm::dvec3(v, 2.0 * v + 0.01, v * v);
  }
  NoiseModel absolute;
  absolute.kind = NoiseKind::kAbsolute;
  absolute.level = 1.0;
  toy->weighting = std::make_unique<Weighting>(toy->table, absolute);
  // The table's quantity (BRDF) and channels (3); residual factors that
  // differ per channel.
  toy->rows = FitRows(toy->table, *toy->weighting);
  for (int i = 0; i < n; ++i) toy->rows.SetScale(i, glm::dvec3(1.0, 0.5, 3.0));
  return toy;
}

// Cost, gradient and J^T J of the toy's problem at x, its residual blocks
// compressed or not.
struct Evaluated {
  double cost;
  Eigen::VectorXd gradient;
  Eigen::MatrixXd jtj;
  int residual_blocks;
};

Evaluated Evaluate(const Toy& toy, const std::vector<double>& x,
                   bool compress) {
  LeastSquaresProblem lsq;
  lsq.block_sizes = {2, 1};
  ResidualBlocks blocks;
  blocks.used = {0, 1};
  SetModelResiduals(std::shared_ptr<const ToyEvaluator>(toy.evaluator),
                    toy.rows, blocks, &lsq);
  std::vector<double> p = x;
  ceres::Problem problem;
  const size_t residuals =
      lsq.add_residuals({p.data(), p.data() + 2}, nullptr, &problem,
                        ResidualRows{nullptr, compress});
  EXPECT_EQ(residuals, toy.rows.size() * 3);
  Evaluated out;
  std::vector<double> gradient;
  ceres::CRSMatrix crs;
  problem.Evaluate(ceres::Problem::EvaluateOptions(), &out.cost, nullptr,
                   &gradient, &crs);
  out.gradient = Eigen::Map<Eigen::VectorXd>(gradient.data(), gradient.size());
  Eigen::MatrixXd j = Eigen::MatrixXd::Zero(crs.num_rows, crs.num_cols);
  for (int r = 0; r < crs.num_rows; ++r) {
    for (int k = crs.rows[r]; k < crs.rows[r + 1]; ++k) {
      j(r, crs.cols[k]) = crs.values[k];
    }
  }
  out.jtj = j.transpose() * j;
  out.residual_blocks = problem.NumResidualBlocks();
  return out;
}

TEST(CompressedRows, CostGradientAndGaussNewtonMatrixAreTheRows) {
  // 1,300 rows: two full chunks and a short one.
  const auto toy = MakeToy(1300);
  const std::vector<double> x = {0.8, 0.7, 0.05};
  const Evaluated rows = Evaluate(*toy, x, false);
  const Evaluated chunks = Evaluate(*toy, x, true);
  EXPECT_EQ(chunks.residual_blocks, 3);
  EXPECT_NEAR(chunks.cost, rows.cost, 1e-12 * rows.cost);
  EXPECT_LT((chunks.gradient - rows.gradient).norm(),
            1e-11 * rows.gradient.norm());
  EXPECT_LT((chunks.jtj - rows.jtj).norm(), 1e-11 * rows.jtj.norm());
}

TEST(CompressedRows, AChunkShorterThanItsColumnsIsKeptWhole) {
  // One row: 3 residuals for 3 parameters plus the residual column.
  const auto toy = MakeToy(1);
  const std::vector<double> x = {0.8, 0.7, 0.05};
  const Evaluated rows = Evaluate(*toy, x, false);
  const Evaluated chunks = Evaluate(*toy, x, true);
  EXPECT_NEAR(chunks.cost, rows.cost, 1e-14);
  EXPECT_LT((chunks.gradient - rows.gradient).norm(), 1e-13);
  EXPECT_LT((chunks.jtj - rows.jtj).norm(), 1e-13);
}

TEST(CompressedRows, ASolveEndsWhereTheRowsSolveEnds) {
  const auto toy = MakeToy(3000);
  std::vector<double> solved[2];
  for (int compress = 0; compress < 2; ++compress) {
    LeastSquaresProblem lsq;
    lsq.block_sizes = {2, 1};
    ResidualBlocks blocks;
    blocks.used = {0, 1};
    SetModelResiduals(std::shared_ptr<const ToyEvaluator>(toy->evaluator),
                      toy->rows, blocks, &lsq);
    std::vector<double> p = {0.5, 1.5, 0.0};
    ceres::Problem problem;
    lsq.add_residuals({p.data(), p.data() + 2}, nullptr, &problem,
                      ResidualRows{nullptr, compress == 1});
    ceres::Solver::Options options;
    options.function_tolerance = 1e-14;
    options.parameter_tolerance = 1e-14;
    options.gradient_tolerance = 1e-16;
    ceres::Solver::Summary summary;
    ceres::Solve(options, &problem, &summary);
    EXPECT_TRUE(summary.IsSolutionUsable()) << summary.BriefReport();
    solved[compress] = p;
  }
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(solved[1][i], solved[0][i], 1e-9) << i;
  }
}

}  // namespace
}  // namespace clothfit
