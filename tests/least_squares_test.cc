// The shared least-squares machinery (fitting/least_squares.h): a model
// value that is not finite during a fit is reported with its row; a
// multi-start prefers a plausible solution; screening many starts solves
// on the best of them.
#include "fitting/least_squares.h"

#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace clothfit {
namespace {

// A toy model with a pole: value = p / wi.z, infinite for a light on the
// horizon (wi.z = 0).
template <typename T>
T PoleModel(const T& p, const TableRow& row) {
  return p / T(row.wi.z);
}

struct PoleResidual {
  explicit PoleResidual(const TableRow& row) : row_(row) {}
  template <typename T>
  bool operator()(const T* p, T* residual) const {
    residual[0] = (PoleModel(p[0], row_) - T(row_.value.x)) / T(row_.sigma.x);
    return true;
  }
  static ceres::CostFunction* Create(const TableRow& row) {
    return new ceres::AutoDiffCostFunction<PoleResidual, 1, 1>(
        new PoleResidual(row));
  }
  const TableRow row_;
};

LeastSquaresProblem PoleProblem(const std::vector<TableRow>& rows) {
  LeastSquaresProblem lsq;
  lsq.specs = {ParameterSpec{"p", 0.0, 10.0, true, true}};
  lsq.block_sizes = {1};
  lsq.add_residuals = [&rows](const std::vector<double*>& blocks,
                              ceres::LossFunction* loss,
                              ceres::Problem* problem, const ResidualRows&) {
    for (const TableRow& row : rows) {
      problem->AddResidualBlock(PoleResidual::Create(row), loss, blocks[0]);
    }
    return rows.size();
  };
  lsq.predict = [&rows](const std::vector<double>& x,
                        const PredictionVisitor& visit) {
    for (const TableRow& row : rows) {
      visit(PoleModel(x[0], row), row.value.x, &row);
    }
  };
  return lsq;
}

// Rows of the model with p = 2 (value 2 / wi.z; 1 on the horizon) at
// lines 3, 4, ... of a table.
std::vector<TableRow> PoleRows(const std::vector<double>& cos_theta) {
  std::vector<TableRow> rows;
  for (size_t i = 0; i < cos_theta.size(); ++i) {
    TableRow row;
    const double c = cos_theta[i];
    row.wi = glm::dvec3(std::sqrt(1.0 - c * c), 0.0, c);
    row.value = glm::dvec3(c > 0.0 ? 2.0 / c : 1.0);
    row.source_line = static_cast<int>(i) + 3;
    rows.push_back(row);
  }
  return rows;
}

TEST(LeastSquaresTest, FiniteModelIsSolvedAndNamesNoRow) {
  const std::vector<TableRow> rows = PoleRows({1.0, 0.8, 0.5, 0.3});
  const LeastSquaresProblem lsq = PoleProblem(rows);
  EXPECT_EQ(NonFiniteRow(lsq, {1.0}), "");
  std::vector<double> x = {1.0};
  const FitReport report = SolveLeastSquares(lsq, {{1.0}}, SolverOptions(), &x);
  ASSERT_TRUE(report.usable) << report.message;
  EXPECT_NEAR(x[0], 2.0, 1e-6);
}

TEST(LeastSquaresTest, NonFiniteModelValueIsReportedWithItsRow) {
  // The third row (line 5) has its light on the horizon: p / 0 = inf.
  const std::vector<TableRow> rows = PoleRows({1.0, 0.8, 0.0, 0.3});
  const LeastSquaresProblem lsq = PoleProblem(rows);
  const std::string where = NonFiniteRow(lsq, {1.0});
  EXPECT_NE(where.find("line 5 of the table"), std::string::npos) << where;
  EXPECT_NE(where.find("inf"), std::string::npos) << where;
  EXPECT_NE(where.find("p = 1"), std::string::npos) << where;

  std::vector<double> x = {1.0};
  const FitReport report = SolveLeastSquares(lsq, {{1.0}}, SolverOptions(), &x);
  EXPECT_FALSE(report.usable);
  EXPECT_NE(report.message.find("line 5 of the table"), std::string::npos)
      << report.message;
  EXPECT_EQ(report.message.find("nan"), std::string::npos) << report.message;
}

TEST(LeastSquaresTest, RowMadeInMemoryIsSaidToBe) {
  std::vector<TableRow> rows = PoleRows({0.0});
  rows[0].source_line = 0;
  const std::string where = NonFiniteRow(PoleProblem(rows), {1.0});
  EXPECT_NE(where.find("a row made in memory"), std::string::npos) << where;
}

// Two basins: r = (p^2 - 4, 0.1 (p - 2)) has its lowest cost at p = 2 and
// another minimum near p = -2 (cost about 0.08).
struct TwoBasins {
  template <typename T>
  bool operator()(const T* p, T* r) const {
    r[0] = p[0] * p[0] - T(4.0);
    r[1] = T(0.1) * (p[0] - T(2.0));
    return true;
  }
};

LeastSquaresProblem TwoBasinProblem() {
  LeastSquaresProblem lsq;
  lsq.specs = {ParameterSpec{"p", -10.0, 10.0, true, true}};
  lsq.block_sizes = {1};
  lsq.add_residuals = [](const std::vector<double*>& blocks,
                         ceres::LossFunction* loss, ceres::Problem* problem,
                         const ResidualRows&) {
    problem->AddResidualBlock(
        new ceres::AutoDiffCostFunction<TwoBasins, 2, 1>(new TwoBasins), loss,
        blocks[0]);
    return size_t{2};
  };
  lsq.predict = [](const std::vector<double>& x,
                   const PredictionVisitor& visit) {
    visit(x[0] * x[0], 4.0, nullptr);
    visit(0.1 * x[0], 0.2, nullptr);
  };
  return lsq;
}

// A multi-start keeps the lowest cost, unless that solution is not
// plausible (as a cloth that reflects more than it receives): then the
// best plausible one, whichever start came first.
TEST(LeastSquaresTest, MultiStartPrefersAPlausibleSolutionToALowerCost) {
  LeastSquaresProblem lsq = TwoBasinProblem();
  std::vector<double> x;
  FitReport report =
      SolveLeastSquares(lsq, {{2.5}, {-2.5}}, SolverOptions(), &x);
  ASSERT_TRUE(report.usable) << report.message;
  EXPECT_NEAR(x[0], 2.0, 1e-6);
  lsq.plausible = [](const std::vector<double>& x) { return x[0] < 0.0; };
  for (const auto& starts : {std::vector<std::vector<double>>{{2.5}, {-2.5}},
                             std::vector<std::vector<double>>{{-2.5}, {2.5}}}) {
    report = SolveLeastSquares(lsq, starts, SolverOptions(), &x);
    ASSERT_TRUE(report.usable) << report.message;
    EXPECT_NEAR(x[0], -2.0, 0.05);
    EXPECT_GT(report.final_cost, 0.01);
  }
  // No plausible solution: the lowest cost, as without the check.
  lsq.plausible = [](const std::vector<double>&) { return false; };
  report = SolveLeastSquares(lsq, {{-2.5}, {2.5}}, SolverOptions(), &x);
  EXPECT_NEAR(x[0], 2.0, 1e-6);
}

// Screening: every start solved a few iterations, the best solved on.
// Without it the stopping rule ends at the first start's basin (p = -2,
// reached once, the rule asks once); with it the start toward p = 2,
// last in the list, is the one solved on.
TEST(LeastSquaresTest, ScreeningSolvesOnTheStartsThatDoBestInAFewIterations) {
  LeastSquaresProblem lsq = TwoBasinProblem();
  lsq.stop_after_hits = 1;
  const std::vector<std::vector<double>> starts = {
      {-2.5}, {-3.0}, {-1.5}, {2.5}};
  std::vector<double> x;
  FitReport report = SolveLeastSquares(lsq, starts, SolverOptions(), &x);
  ASSERT_TRUE(report.usable) << report.message;
  EXPECT_NEAR(x[0], -2.0, 0.05);
  EXPECT_EQ(report.starts, 1);

  lsq.screen_iterations = 2;
  lsq.screen_keep = 1;
  report = SolveLeastSquares(lsq, starts, SolverOptions(), &x);
  ASSERT_TRUE(report.usable) << report.message;
  EXPECT_NEAR(x[0], 2.0, 1e-6);
  EXPECT_TRUE(report.converged) << report.message;
  EXPECT_EQ(report.starts, 1);
  EXPECT_NE(report.search.find("4 starts screened (at most 2 iterations "
                               "each), the best 1 solved on"),
            std::string::npos)
      << report.search;
  // The screening's iterations count with the solve's.
  EXPECT_GE(report.iterations, 4);

  // No more starts than are kept: nothing to screen.
  report = SolveLeastSquares(lsq, {{-2.5}}, SolverOptions(), &x);
  EXPECT_EQ(report.search.find("screened"), std::string::npos) << report.search;
  EXPECT_NEAR(x[0], -2.0, 0.05);
}

// A plausible screened solution is solved on before any implausible one,
// however much lower the latter's cost.
TEST(LeastSquaresTest, ScreeningKeepsAPlausibleStartOverALowerCost) {
  LeastSquaresProblem lsq = TwoBasinProblem();
  lsq.stop_after_hits = 1;
  lsq.screen_iterations = 3;
  lsq.screen_keep = 1;
  int checks = 0;
  lsq.plausible = [&checks](const std::vector<double>& x) {
    ++checks;
    return x[0] < 0.0;
  };
  std::vector<double> x;
  const FitReport report =
      SolveLeastSquares(lsq, {{2.5}, {2.2}, {-2.5}}, SolverOptions(), &x);
  ASSERT_TRUE(report.usable) << report.message;
  EXPECT_NEAR(x[0], -2.0, 0.05);
  // Checked lowest cost first until one is plausible (all three here),
  // then the solution solved on: 4 checks, not one per start and solve
  // beyond that.
  EXPECT_EQ(checks, 4);
}

}  // namespace
}  // namespace clothfit
