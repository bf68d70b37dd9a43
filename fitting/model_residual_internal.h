// The one residual of the least-squares fits (thread, cloth, slab, holes):
// a model evaluated through models/ with Jets, weighted by
// fitting/residual_weight.h. A fit supplies an evaluator, a const object
// shared by all rows with
//
//   template <typename T>
//   Vec3<T> operator()(const T* const* blocks, size_t i) const;
//
// the model's value for its row i from the parameter blocks (the same code
// runs with double for predictions and with Jets for Ceres). The rows'
// residuals are DynamicAutoDiffCostFunctions over the blocks the fit
// names, so that any number of blocks (a weave of 1 to 3 threads, with or
// without its coverage blocks and the scale) needs no code per layout, and
// blocks held constant cost no derivatives; Ceres sees a chunk of rows as
// one block of few residuals (ResidualRows::compress), so that its memory
// and overhead do not grow with the rows' residuals. Includes Ceres: for
// fitting/*.cc only (not installed).
#pragma once

#include <ceres/ceres.h>

#include <memory>
#include <vector>

#include "fitting/flatten_internal.h"
#include "fitting/least_squares.h"
#include "fitting/residual_weight.h"
#include "models/math.h"

namespace clothfit {

// One row of a fit: the table row, the quantity it holds, the number of
// its channels that are residuals (1 or 3), the weighting of its table
// (which must outlive the fit) and the factors sqrt(weight) / sigma of its
// residuals (Weighting::Scale, then ScaleAt the fitted model).
struct FitRow {
  const TableRow* row;
  Quantity quantity;
  int channels;
  const Weighting* weighting;
  glm::dvec3 scale;
};

// The blocks a fit's residuals use: indices into LeastSquaresProblem's
// blocks, and (scale >= 0) the block whose one entry multiplies the model
// (data on an arbitrary scale).
struct ResidualBlocks {
  std::vector<int> used;
  int scale = -1;  // index into `used`, or -1
};

// The residuals of rows [begin, end) of a list (`subset`, or the rows
// themselves when it is null), channel by channel: a functor for
// DynamicAutoDiffCostFunction.
template <class Evaluator>
class ModelResidual {
 public:
  // Derivative lanes per pass of DynamicAutoDiffCostFunction: a thread's
  // seven parameters and the scale in one pass.
  static constexpr int kStride = 8;
  using Cost = ceres::DynamicAutoDiffCostFunction<ModelResidual, kStride>;

  ModelResidual(std::shared_ptr<const Evaluator> evaluator,
                std::shared_ptr<const std::vector<FitRow>> rows,
                std::shared_ptr<const std::vector<uint32_t>> subset,
                size_t begin, size_t end, int scale_block)
      : evaluator_(std::move(evaluator)),
        rows_(std::move(rows)),
        subset_(std::move(subset)),
        begin_(begin),
        end_(end),
        scale_block_(scale_block) {}

  size_t Row(size_t k) const { return subset_ ? (*subset_)[k] : k; }

  // The number of residuals: the channels of the rows.
  int Residuals() const {
    int n = 0;
    for (size_t k = begin_; k < end_; ++k) n += (*rows_)[Row(k)].channels;
    return n;
  }

  template <typename T>
  CLOTHFIT_FLATTEN bool operator()(const T* const* blocks, T* residual) const {
    for (size_t k = begin_; k < end_; ++k) {
      const size_t i = Row(k);
      const FitRow& row = (*rows_)[i];
      Vec3<T> model = (*evaluator_)(blocks, i);
      if (scale_block_ >= 0) model *= blocks[scale_block_][0];
      for (int c = 0; c < row.channels; ++c) {
        *residual++ =
            WeightedResidual(model[c], row.row->value[c], row.scale[c]);
      }
    }
    return true;
  }

  static Cost* Create(ModelResidual* functor, const ResidualBlocks& blocks,
                      const std::vector<int>& block_sizes) {
    auto* cost = new Cost(functor);
    for (int b : blocks.used) cost->AddParameterBlock(block_sizes[b]);
    cost->SetNumResiduals(functor->Residuals());
    return cost;
  }

 private:
  std::shared_ptr<const Evaluator> evaluator_;
  std::shared_ptr<const std::vector<FitRow>> rows_;
  std::shared_ptr<const std::vector<uint32_t>> subset_;
  size_t begin_, end_;
  int scale_block_;
};

// Rows per compressed residual block (ResidualRows::compress).
inline constexpr size_t kChunkRows = 512;

// Adds the compressed residual block of a cost over many rows
// (fitting/compressed_rows.cc): takes ownership of `rows`.
void AddCompressedRows(ceres::CostFunction* rows,
                       const std::vector<double*>& blocks,
                       ceres::Problem* problem);

// Sets lsq->add_residuals, lsq->predict and lsq->reweight for `rows`
// evaluated by `evaluator` (row i of the evaluator is rows[i]) over
// `blocks`.
template <class Evaluator>
void SetModelResiduals(std::shared_ptr<const Evaluator> evaluator,
                       std::vector<FitRow> rows_in, ResidualBlocks blocks,
                       LeastSquaresProblem* lsq) {
  const std::vector<int> sizes = lsq->block_sizes;
  // Shared by the three: reweight changes the scales the next solve uses.
  auto rows = std::make_shared<std::vector<FitRow>>(std::move(rows_in));
  lsq->rows = rows->size();
  lsq->add_residuals = [=](const std::vector<double*>& x,
                           ceres::LossFunction* loss, ceres::Problem* problem,
                           const ResidualRows& which) {
    std::vector<double*> used;
    for (int b : blocks.used) used.push_back(x[b]);
    std::shared_ptr<const std::vector<uint32_t>> subset;
    if (which.subset) {
      subset = std::make_shared<const std::vector<uint32_t>>(*which.subset);
    }
    const size_t n = subset ? subset->size() : rows->size();
    // A robust loss acts on each row's residuals: one block per row.
    const size_t chunk = loss == nullptr ? kChunkRows : 1;
    size_t residuals = 0;
    for (size_t begin = 0; begin < n; begin += chunk) {
      auto* functor = new ModelResidual<Evaluator>(
          evaluator, rows, subset, begin, std::min(n, begin + chunk),
          blocks.scale);
      residuals += functor->Residuals();
      auto* cost = ModelResidual<Evaluator>::Create(functor, blocks, sizes);
      if (chunk > 1 && which.compress) {
        AddCompressedRows(cost, used, problem);
      } else {
        problem->AddResidualBlock(cost, loss, used);
      }
    }
    return residuals;
  };
  // Calls each(i, value) with the model value of every row i at x, in
  // data units.
  auto values = [=](const std::vector<double>& x, const auto& each) {
    std::vector<const double*> used;
    std::vector<int> offsets(sizes.size() + 1, 0);
    for (size_t b = 0; b < sizes.size(); ++b) {
      offsets[b + 1] = offsets[b] + sizes[b];
    }
    for (int b : blocks.used) used.push_back(x.data() + offsets[b]);
    const double s = blocks.scale >= 0 ? used[blocks.scale][0] : 1.0;
    for (size_t i = 0; i < rows->size(); ++i) {
      each(i, (*evaluator)(used.data(), i) * s);
    }
  };
  lsq->row = [rows](size_t i) { return (*rows)[i].row; };
  lsq->predict = [=](const std::vector<double>& x,
                     const PredictionVisitor& visit) {
    values(x, [&](size_t i, const glm::dvec3& m) {
      const FitRow& row = (*rows)[i];
      for (int c = 0; c < row.channels; ++c) {
        visit(m[c], row.row->value[c], row.row);
      }
    });
  };
  bool depends = false;
  for (const FitRow& row : *rows) {
    depends = depends || row.weighting->DependsOnModel();
  }
  if (!depends) return;
  lsq->reweight = [=](const std::vector<double>& x) {
    values(x, [&](size_t i, const glm::dvec3& m) {
      FitRow& row = (*rows)[i];
      row.scale = row.weighting->ScaleAt(*row.row, m);
    });
  };
}

// One FitRow per row of a table, with the table's quantity and channels,
// weighted by `weighting` (which must outlive them).
inline std::vector<FitRow> TableFitRows(const MeasurementTable& table,
                                        const Weighting& weighting) {
  std::vector<FitRow> rows;
  rows.reserve(table.rows.size());
  for (const TableRow& row : table.rows) {
    rows.push_back({&row, table.quantity, table.channels, &weighting,
                    weighting.Scale(row)});
  }
  return rows;
}

}  // namespace clothfit
