// Standard deviations from the Jacobian of a least-squares fit at its
// solution, shared by the fits (least_squares.cc, lafortune_covariance.cc).
// Eigen stays inside fitting/. For fitting/*.cc only.
#pragma once

#include <Eigen/Dense>
#include <functional>
#include <vector>

namespace clothfit {

// What a Jacobian's columns come to: per column, its standard deviation
// and (when asked for) the sandwich estimate, -1 where not available; the
// columns the data cannot determine. Those have no standard deviation;
// the others' are then conditional: their covariance with the columns
// that are not identifiable held at their values (the covariance of the
// Jacobian without those columns; the matrices below are 0 in their rows
// and columns). A column with no effect (zero) changes nothing by being
// held; for a combination the data nearly determine, the conditional
// standard deviations are a lower bound. None when every column is named
// or J has fewer rows than columns.
struct ColumnCovariance {
  std::vector<double> stddev, sandwich;
  std::vector<int> not_identifiable;
  bool conditional = false;
  // The whole matrices (columns x columns; empty where not available), for
  // a report in other variables (delta method, least_squares.cc).
  Eigen::MatrixXd covariance, sandwich_covariance;
};

// J: residuals x free parameters, of the weighted residuals r (the
// solution's). Columns are scaled to unit norm first (D = diag |J_c|), so
// that units do not decide what counts as rank-deficient: albedo (~0.01)
// and gamma_v_deg (~60) differ by four orders of magnitude, enough for
// ceres::Covariance, which tests the condition of the unscaled J^T J, to
// call a well-determined problem singular. With J D^-1 = U S V^T,
//   Cov = D^-1 V S^-2 V^T D^-1 * s2,
// s2 = 1 when sigma is known (sigma_known), else the residual variance
// 2 cost / dof, dof = residuals - columns (`residuals` may count more than
// J's rows: merged samples stand for their rows; cost = |r|^2 / 2 without
// a robust loss). A
// singular value below kMinSingularRatio * s_max means the data cannot
// determine the combination of parameters in its right singular vector:
// its columns (|v| > 0.2) are not identifiable, as is a zero column and
// every column when J has fewer rows than columns. With sigma unknown the
// sandwich (White's heteroscedasticity-consistent estimate, HC1) is given
// too: (J^T J)^-1 J^T diag(r^2) J (J^T J)^-1 n / (n - p), valid whatever
// the noise level and its variation across rows.
//
// J may also be any matrix with the rows' J^T J (the triangular factors of
// chunks of rows, fitting/compressed_rows.cc): the SVD's singular values
// and V, hence Cov, are the same. The sandwich needs each row's leverage:
// then `rows` visits the rows' own Jacobian (same columns) and residuals,
// in blocks, by calling its argument once per block.
inline constexpr double kMinSingularRatio = 1e-7;
using RowBlockVisitor =
    std::function<void(const std::function<void(const Eigen::MatrixXd& j,
                                                const Eigen::VectorXd& r)>&)>;
ColumnCovariance CovarianceOfColumns(const Eigen::MatrixXd& j,
                                     const Eigen::VectorXd& r, bool sigma_known,
                                     double cost, int residuals,
                                     const RowBlockVisitor& rows = nullptr);

}  // namespace clothfit
