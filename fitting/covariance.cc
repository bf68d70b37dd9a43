#include <algorithm>
#include <cmath>

#include "fitting/covariance_internal.h"

namespace clothfit {

ColumnCovariance CovarianceOfColumns(const Eigen::MatrixXd& j,
                                     const Eigen::VectorXd& r, bool sigma_known,
                                     double cost, int residuals,
                                     const RowBlockVisitor& rows) {
  const int n = static_cast<int>(j.cols());
  ColumnCovariance out;
  out.stddev.assign(n, -1.0);
  out.sandwich.assign(n, -1.0);
  if (n == 0) return out;
  // With the rows visited for the sandwich, J only has to carry the rows'
  // J^T J, which its triangular QR factor (n x n) does: the same singular
  // values and V below, from n rows instead of J's (the compressed chunks
  // of 10^7 rows are some 50 MB, which the SVD copied three times).
  if (rows && j.rows() > n) {
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(j);
    const Eigen::MatrixXd factor =
        qr.matrixQR().topRows(n).triangularView<Eigen::Upper>();
    return CovarianceOfColumns(factor, Eigen::VectorXd(), sigma_known, cost,
                               residuals, rows);
  }
  auto flag = [&](int c) {
    if (std::find(out.not_identifiable.begin(), out.not_identifiable.end(),
                  c) == out.not_identifiable.end()) {
      out.not_identifiable.push_back(c);
    }
  };
  Eigen::VectorXd norms = j.colwise().norm();
  for (int c = 0; c < n; ++c) {
    if (!(norms[c] > 0.0)) {
      flag(c);
      norms[c] = 1.0;
    }
  }
  const Eigen::MatrixXd scaled = j * norms.cwiseInverse().asDiagonal();
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(scaled, Eigen::ComputeThinV);
  const Eigen::VectorXd sv = svd.singularValues();
  const Eigen::MatrixXd& v = svd.matrixV();
  const double s_max = sv.size() > 0 ? sv[0] : 0.0;
  for (int k = 0; k < sv.size(); ++k) {
    if (sv[k] > kMinSingularRatio * s_max) continue;
    for (int c = 0; c < n; ++c) {
      if (std::abs(v(c, k)) > 0.2) flag(c);
    }
  }
  if (sv.size() < n) {  // fewer residuals than free parameters
    for (int c = 0; c < n; ++c) flag(c);
  }
  if (!out.not_identifiable.empty()) {
    std::sort(out.not_identifiable.begin(), out.not_identifiable.end());
    const int held = static_cast<int>(out.not_identifiable.size());
    if (held == n || sv.size() < n) return out;
    // The others' covariance with these held at their values: that of
    // the Jacobian's other columns (which may name more).
    std::vector<int> kept;
    for (int c = 0; c < n; ++c) {
      if (!std::binary_search(out.not_identifiable.begin(),
                              out.not_identifiable.end(), c)) {
        kept.push_back(c);
      }
    }
    RowBlockVisitor kept_rows = nullptr;
    if (rows) {
      kept_rows = [&](const auto& visit) {
        rows([&](const Eigen::MatrixXd& jb, const Eigen::VectorXd& rb) {
          const Eigen::MatrixXd kept_jb = jb(Eigen::all, kept);
          visit(kept_jb, rb);
        });
      };
    }
    const Eigen::MatrixXd kept_j = j(Eigen::all, kept);
    const ColumnCovariance sub =
        CovarianceOfColumns(kept_j, r, sigma_known, cost, residuals, kept_rows);
    for (int c : sub.not_identifiable) flag(kept[c]);
    std::sort(out.not_identifiable.begin(), out.not_identifiable.end());
    if (sub.covariance.rows() != static_cast<int>(kept.size())) return out;
    out.conditional = true;
    out.covariance = Eigen::MatrixXd::Zero(n, n);
    out.covariance(kept, kept) = sub.covariance;
    if (sub.sandwich_covariance.rows() == sub.covariance.rows()) {
      out.sandwich_covariance = Eigen::MatrixXd::Zero(n, n);
      out.sandwich_covariance(kept, kept) = sub.sandwich_covariance;
    }
    for (size_t k = 0; k < kept.size(); ++k) {
      out.stddev[kept[k]] = sub.stddev[k];
      out.sandwich[kept[k]] = sub.sandwich[k];
    }
    return out;
  }
  const int dof = residuals - n;
  const bool has_r = rows != nullptr || r.size() == j.rows();
  const double s2 = sigma_known || dof <= 0 ? 1.0 : 2.0 * cost / dof;
  const Eigen::MatrixXd w = v * sv.cwiseInverse().asDiagonal();
  const Eigen::MatrixXd wd = norms.cwiseInverse().asDiagonal() * w;
  out.covariance = wd * wd.transpose() * s2;
  for (int c = 0; c < n; ++c) {
    out.stddev[c] = std::sqrt(out.covariance(c, c));
  }
  // With J D^-1 = U S V^T the sandwich is D^-1 A A^T D^-1,
  // A = V S^-1 U^T diag(e), e_i = r_i / (1 - h_i) with the leverage h_i =
  // |U_i|^2 (HC3, MacKinnon and White 1985): a residual of a row that
  // pulls the fit toward itself is smaller than its noise, most so where
  // few rows decide a parameter (a narrow lobe's peak), which HC1's
  // uniform n / (n - p) leaves too confident.
  //   A A^T = D^-1 W (sum_i e_i^2 U_i^T U_i) W^T D^-1, W = V S^-1,
  // with U's row i = J_i D^-1 W: the sum runs over the rows in blocks.
  if (!sigma_known && dof > 0 && has_r) {
    Eigen::MatrixXd meat = Eigen::MatrixXd::Zero(n, n);
    const Eigen::MatrixXd dw = norms.cwiseInverse().asDiagonal() * w;
    auto add = [&](const Eigen::MatrixXd& jb, const Eigen::VectorXd& rb) {
      Eigen::MatrixXd u = jb * dw;
      for (int i = 0; i < rb.size(); ++i) {  // rows e_i U_i
        const double h = std::min(u.row(i).squaredNorm(), 1.0 - 1e-12);
        u.row(i) *= rb[i] / (1.0 - h);
      }
      meat.noalias() += u.transpose() * u;
    };
    if (rows) {
      rows(add);
    } else {
      add(j, r);
    }
    out.sandwich_covariance = dw * meat * dw.transpose();
    for (int c = 0; c < n; ++c) {
      out.sandwich[c] = std::sqrt(out.sandwich_covariance(c, c));
    }
  }
  return out;
}

}  // namespace clothfit
