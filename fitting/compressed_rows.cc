// A chunk of rows as one residual block of few residuals: the triangular
// factor of the QR decomposition of the rows' [J | r] (ResidualRows in
// fitting/least_squares.h). For [J r] = Q R with R upper triangular,
// R^T R = [J r]^T [J r]: the block's residuals r' = R(:, n) and Jacobian
// J' = R(:, 0..n) give J'^T J' = J^T J, J'^T r' = J^T r and
// |r'|^2 = |r|^2, so |J' d + r'|^2 = |J d + r|^2 for every step d: the
// trust-region solver takes the steps the rows themselves would give it
// (Golub and Van Loan, Matrix Computations, 5.3: least squares by QR).
#include <ceres/ceres.h>

#include <Eigen/Dense>
#include <memory>
#include <vector>

#include "fitting/model_residual_internal.h"

namespace clothfit {
namespace {

class CompressedRows : public ceres::CostFunction {
 public:
  explicit CompressedRows(ceres::CostFunction* rows) : rows_(rows) {
    int columns = 0;
    for (int size : rows_->parameter_block_sizes()) {
      mutable_parameter_block_sizes()->push_back(size);
      columns += size;
    }
    // Every column and the residual: R is (columns + 1) square at most.
    set_num_residuals(columns + 1);
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const int m = rows_->num_residuals();
    const int out = num_residuals();
    thread_local std::vector<double> r;
    r.resize(m);
    std::fill(residuals, residuals + out, 0.0);
    const std::vector<int32_t>& sizes = parameter_block_sizes();
    if (jacobians == nullptr) {
      // The cost alone: any vector of the rows' norm.
      if (!rows_->Evaluate(parameters, r.data(), nullptr)) return false;
      residuals[out - 1] =
          Eigen::Map<const Eigen::VectorXd>(r.data(), m).norm();
      return true;
    }
    // The rows' Jacobians of the blocks asked for (row-major, m x size).
    thread_local std::vector<std::vector<double>> j;
    thread_local std::vector<double*> j_ptr;
    j.resize(sizes.size());
    j_ptr.assign(sizes.size(), nullptr);
    int columns = 0;
    for (size_t b = 0; b < sizes.size(); ++b) {
      if (jacobians[b] == nullptr) continue;
      j[b].resize(static_cast<size_t>(m) * sizes[b]);
      j_ptr[b] = j[b].data();
      columns += sizes[b];
    }
    if (!rows_->Evaluate(parameters, r.data(), j_ptr.data())) return false;
    Eigen::MatrixXd a(m, columns + 1);
    int col = 0;
    for (size_t b = 0; b < sizes.size(); ++b) {
      if (jacobians[b] == nullptr) continue;
      for (int i = 0; i < sizes[b]; ++i, ++col) {
        for (int k = 0; k < m; ++k) a(k, col) = j[b][k * sizes[b] + i];
      }
    }
    for (int k = 0; k < m; ++k) a(k, columns) = r[k];
    Eigen::HouseholderQR<Eigen::Ref<Eigen::MatrixXd>> qr(a);
    // R's rows (upper triangular; fewer than columns + 1 when m is).
    const int kept = std::min(m, columns + 1);
    for (int k = 0; k < kept; ++k) residuals[k] = a(k, columns);
    col = 0;
    for (size_t b = 0; b < sizes.size(); ++b) {
      if (jacobians[b] == nullptr) continue;
      std::fill(jacobians[b], jacobians[b] + out * sizes[b], 0.0);
      for (int i = 0; i < sizes[b]; ++i, ++col) {
        for (int k = 0; k < kept && k <= col; ++k) {
          jacobians[b][k * sizes[b] + i] = a(k, col);
        }
      }
    }
    return true;
  }

 private:
  std::unique_ptr<ceres::CostFunction> rows_;
};

}  // namespace

void AddCompressedRows(ceres::CostFunction* rows,
                       const std::vector<double*>& blocks,
                       ceres::Problem* problem) {
  problem->AddResidualBlock(new CompressedRows(rows), nullptr, blocks);
}

}  // namespace clothfit
