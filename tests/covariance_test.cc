// Standard deviations from a fit's Jacobian (fitting/covariance.cc): the
// columns the data cannot determine are named, and the others' standard
// deviations are those with the named columns held at their values,
// checked against the textbook formulas computed here.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <vector>

#include "fitting/covariance_internal.h"

namespace clothfit {
namespace {

// A deterministic, well-conditioned m x 1 column.
Eigen::VectorXd Column(int m, double phase) {
  Eigen::VectorXd c(m);
  for (int i = 0; i < m; ++i) c[i] = std::sin(0.37 * i + phase) + 0.1 * phase;
  return c;
}

// sqrt(diag((J^T J)^-1)) with sigma known.
Eigen::VectorXd Textbook(const Eigen::MatrixXd& j) {
  return (j.transpose() * j).inverse().diagonal().cwiseSqrt();
}

// HC3 (MacKinnon and White 1985): (J^T J)^-1 J^T diag(e^2) J (J^T J)^-1,
// e_i = r_i / (1 - h_i), h_i = J_i (J^T J)^-1 J_i^T.
Eigen::VectorXd TextbookHc3(const Eigen::MatrixXd& j,
                            const Eigen::VectorXd& r) {
  const Eigen::MatrixXd bread = (j.transpose() * j).inverse();
  Eigen::MatrixXd meat = Eigen::MatrixXd::Zero(j.cols(), j.cols());
  for (int i = 0; i < j.rows(); ++i) {
    const double h = j.row(i) * bread * j.row(i).transpose();
    const double e = r[i] / (1.0 - h);
    meat += e * e * j.row(i).transpose() * j.row(i);
  }
  return (bread * meat * bread).diagonal().cwiseSqrt();
}

TEST(CovarianceOfColumns, AZeroColumnIsNamedAndTheOthersKeepTheirStddev) {
  const int m = 40;
  Eigen::MatrixXd j(m, 3);
  j << Column(m, 0.0), Eigen::VectorXd::Zero(m), Column(m, 1.3);
  const Eigen::VectorXd r = Eigen::VectorXd::Zero(m);
  const ColumnCovariance cov = CovarianceOfColumns(j, r, true, 0.0, m);
  ASSERT_EQ(cov.not_identifiable, std::vector<int>{1});
  EXPECT_TRUE(cov.conditional);
  Eigen::MatrixXd kept(m, 2);
  kept << j.col(0), j.col(2);
  const Eigen::VectorXd want = Textbook(kept);
  EXPECT_NEAR(cov.stddev[0], want[0], 1e-12 * want[0]);
  EXPECT_NEAR(cov.stddev[2], want[1], 1e-12 * want[1]);
  EXPECT_EQ(cov.stddev[1], -1.0);
  ASSERT_EQ(cov.covariance.rows(), 3);
  EXPECT_EQ(cov.covariance.row(1).norm(), 0.0);
  EXPECT_EQ(cov.covariance.col(1).norm(), 0.0);
}

// Columns 0 and 1 move the residuals alike (a combination the data cannot
// tell apart): both are named; column 2, held apart from them, keeps the
// standard deviation of a fit of it alone.
TEST(CovarianceOfColumns, ACombinationNamesItsColumnsAndHoldsThemForTheOthers) {
  const int m = 40;
  const Eigen::VectorXd a = Column(m, 0.4), b = Column(m, 2.1);
  Eigen::MatrixXd j(m, 3);
  j << a, -2.5 * a, b;
  const ColumnCovariance cov =
      CovarianceOfColumns(j, Eigen::VectorXd::Zero(m), true, 0.0, m);
  ASSERT_EQ(cov.not_identifiable, (std::vector<int>{0, 1}));
  EXPECT_TRUE(cov.conditional);
  EXPECT_NEAR(cov.stddev[2], 1.0 / b.norm(), 1e-12 / b.norm());
  EXPECT_EQ(cov.stddev[0], -1.0);
  EXPECT_EQ(cov.stddev[1], -1.0);
}

// With the noise level unknown: the residual variance over the kept
// columns' degrees of freedom, and the sandwich of the rows visited in
// blocks, both as if the named column were not there.
TEST(CovarianceOfColumns,
     HeldColumnsLeaveTheScaledAndSandwichEstimatesOfTheOthers) {
  const int m = 30;
  Eigen::MatrixXd j(m, 3);
  j << Column(m, 0.9), Column(m, 2.7), Eigen::VectorXd::Zero(m);
  Eigen::VectorXd r(m);
  for (int i = 0; i < m; ++i) r[i] = 0.05 * std::cos(1.7 * i) * (1 + i % 3);
  const double cost = 0.5 * r.squaredNorm();
  // The rows in blocks of 7, as a compressed fit visits them.
  const RowBlockVisitor blocks = [&](const auto& visit) {
    for (int begin = 0; begin < m; begin += 7) {
      const int n = std::min(7, m - begin);
      visit(j.middleRows(begin, n), r.segment(begin, n));
    }
  };
  const ColumnCovariance cov =
      CovarianceOfColumns(j, r, false, cost, m, blocks);
  ASSERT_EQ(cov.not_identifiable, std::vector<int>{2});
  const Eigen::MatrixXd kept = j.leftCols(2);
  const double s2 = r.squaredNorm() / (m - 2);
  const Eigen::VectorXd want = Textbook(kept) * std::sqrt(s2);
  const Eigen::VectorXd hc3 = TextbookHc3(kept, r);
  for (int c = 0; c < 2; ++c) {
    EXPECT_NEAR(cov.stddev[c], want[c], 1e-10 * want[c]) << c;
    EXPECT_NEAR(cov.sandwich[c], hc3[c], 1e-10 * hc3[c]) << c;
  }
  EXPECT_EQ(cov.sandwich[2], -1.0);
}

// Fewer rows than columns: nothing is determined, nothing is held.
TEST(CovarianceOfColumns, FewerRowsThanColumnsGiveNoStddevAtAll) {
  Eigen::MatrixXd j(2, 3);
  j << 1.0, 0.0, 2.0, 0.0, 1.0, 1.0;
  const ColumnCovariance cov =
      CovarianceOfColumns(j, Eigen::VectorXd::Zero(2), true, 0.0, 2);
  EXPECT_EQ(cov.not_identifiable, (std::vector<int>{0, 1, 2}));
  EXPECT_FALSE(cov.conditional);
  for (double s : cov.stddev) EXPECT_EQ(s, -1.0);
}

}  // namespace
}  // namespace clothfit
