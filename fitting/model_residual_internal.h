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

#include "fitting/energy_bound_tables_internal.h"
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

// The rows of a fit: every row of one or more tables (the slab's
// reflectance and transmittance), in order, as FitRows. What is held per
// row is its residual factors alone (24 bytes); the row, its quantity,
// channels and weighting are looked up in its table, which with its
// weighting must outlive the fit. A table of 10^7 rows costs 0.23 GiB
// here beside its own rows, not 0.45 GiB for a copy of each FitRow.
class FitRows {
 public:
  FitRows() = default;
  FitRows(const MeasurementTable& table, const Weighting& weighting) {
    Append(table, weighting);
  }

  // Appends every row of `table`, factors from `weighting`.
  void Append(const MeasurementTable& table, const Weighting& weighting) {
    sources_.push_back({&table, &weighting, scale_.size()});
    scale_.reserve(scale_.size() + table.rows.size());
    for (const TableRow& row : table.rows) {
      scale_.push_back(weighting.Scale(row));
    }
  }

  size_t size() const { return scale_.size(); }

  FitRow operator[](size_t i) const {
    const Source& s = SourceOf(i);
    return {&s.table->rows[i - s.begin], s.table->quantity, s.table->channels,
            s.weighting, scale_[i]};
  }

  // Replaces row i's residual factors (a reweighting's ScaleAt).
  void SetScale(size_t i, const glm::dvec3& scale) { scale_[i] = scale; }

  // Whether any table's weighting depends on the model (relative noise).
  bool DependsOnModel() const {
    for (const Source& s : sources_) {
      if (s.weighting->DependsOnModel()) return true;
    }
    return false;
  }

  // Range-for over the rows, each a FitRow by value.
  class Iterator {
   public:
    Iterator(const FitRows* rows, size_t i) : rows_(rows), i_(i) {}
    FitRow operator*() const { return (*rows_)[i_]; }
    Iterator& operator++() {
      ++i_;
      return *this;
    }
    bool operator!=(const Iterator& other) const { return i_ != other.i_; }

   private:
    const FitRows* rows_;
    size_t i_;
  };
  Iterator begin() const { return Iterator(this, 0); }
  Iterator end() const { return Iterator(this, size()); }

 private:
  struct Source {
    const MeasurementTable* table;
    const Weighting* weighting;
    size_t begin;  // index of the table's first row
  };
  // The table of row i: the last one that begins at or before it (an
  // empty table begins where the next one does).
  const Source& SourceOf(size_t i) const {
    size_t k = sources_.size() - 1;
    while (i < sources_[k].begin) --k;
    return sources_[k];
  }
  std::vector<Source> sources_;
  std::vector<glm::dvec3> scale_;
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

  // bound: the energy bound's tables as a function of the blocks (a fit
  // of the bounded model), or null.
  ModelResidual(std::shared_ptr<const Evaluator> evaluator,
                std::shared_ptr<const FitRows> rows,
                std::shared_ptr<const std::vector<uint32_t>> subset,
                size_t begin, size_t end, int scale_block,
                std::shared_ptr<const BoundTables> bound = nullptr)
      : evaluator_(std::move(evaluator)),
        rows_(std::move(rows)),
        subset_(std::move(subset)),
        begin_(begin),
        end_(end),
        scale_block_(scale_block),
        bound_(std::move(bound)) {}

  size_t Row(size_t k) const { return subset_ ? (*subset_)[k] : k; }

  // The number of residuals: the channels of the rows.
  int Residuals() const {
    int n = 0;
    for (size_t k = begin_; k < end_; ++k) n += (*rows_)[Row(k)].channels;
    return n;
  }

  template <typename T>
  CLOTHFIT_FLATTEN bool operator()(const T* const* blocks, T* residual) const {
    constexpr int n = kEnergyBoundNodes;
    std::vector<T> tables(bound_ ? 2 * n : 0);
    if (bound_ && !(*bound_)(blocks, tables.data())) return false;
    for (size_t k = begin_; k < end_; ++k) {
      const size_t i = Row(k);
      const FitRow row = (*rows_)[i];
      Vec3<T> model = (*evaluator_)(blocks, i);
      if (scale_block_ >= 0) model *= blocks[scale_block_][0];
      if (bound_) {
        model *= EnergyBoundFactorOf<T>(tables.data(), tables.data() + n, n,
                                        row.row->wi.z, row.row->wo.z);
      }
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
  std::shared_ptr<const FitRows> rows_;
  std::shared_ptr<const std::vector<uint32_t>> subset_;
  size_t begin_, end_;
  int scale_block_;
  std::shared_ptr<const BoundTables> bound_;
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
// `blocks`. With a plan, the model is the bounded one (models/bounded.h)
// whose tables follow the parameters through that plan
// (fitting/energy_bound_tables_internal.h; the evaluator supplies
// BoundRho).
template <class Evaluator>
void SetModelResiduals(std::shared_ptr<const Evaluator> evaluator,
                       FitRows rows_in, ResidualBlocks blocks,
                       LeastSquaresProblem* lsq,
                       const EnergyBoundPlan* plan = nullptr) {
  const std::vector<int> sizes = lsq->block_sizes;
  std::shared_ptr<const BoundTables> bound;
  if constexpr (HasBoundRho<Evaluator>::value) {
    if (plan) {
      std::vector<int> used_sizes;
      for (int b : blocks.used) used_sizes.push_back(sizes[b]);
      bound = MakeBoundTables(evaluator, *plan, used_sizes, blocks.scale);
    }
  }
  // Shared by the three: reweight changes the scales the next solve uses.
  auto rows = std::make_shared<FitRows>(std::move(rows_in));
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
          blocks.scale, bound);
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
    constexpr int n = kEnergyBoundNodes;
    std::vector<double> tables(bound ? 2 * n : 0);
    if (bound) (*bound)(used.data(), tables.data());
    for (size_t i = 0; i < rows->size(); ++i) {
      const TableRow& row = *(*rows)[i].row;
      const double factor =
          bound ? EnergyBoundFactorOf<double>(tables.data(), tables.data() + n,
                                              n, row.wi.z, row.wo.z)
                : 1.0;
      each(i, (*evaluator)(used.data(), i) * (s * factor));
    }
  };
  lsq->row = [rows](size_t i) { return (*rows)[i].row; };
  lsq->predict = [=](const std::vector<double>& x,
                     const PredictionVisitor& visit) {
    values(x, [&](size_t i, const glm::dvec3& m) {
      const FitRow row = (*rows)[i];
      for (int c = 0; c < row.channels; ++c) {
        visit(m[c], row.row->value[c], row.row);
      }
    });
  };
  if (!rows->DependsOnModel()) return;
  lsq->reweight = [=](const std::vector<double>& x) {
    values(x, [&](size_t i, const glm::dvec3& m) {
      const FitRow row = (*rows)[i];
      rows->SetScale(i, row.weighting->ScaleAt(*row.row, m));
    });
  };
}

// The FitRows of every row of a table, weighted by `weighting` (which,
// like the table, must outlive them).
inline FitRows TableFitRows(const MeasurementTable& table,
                            const Weighting& weighting) {
  return FitRows(table, weighting);
}

}  // namespace clothfit
