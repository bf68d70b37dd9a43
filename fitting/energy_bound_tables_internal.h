// The energy bound's tables (models/energy_bound.h) as a function of a
// fit's parameter blocks, so that a fit of the bounded model sees how the
// bound moves with the parameters: the tables are quadratures of the model
// itself, and a solve that held them fixed would take a brighter model for
// free (its bound, recomputed, divides the brightness out again).
//
// With the plan (each entry's azimuth, channel and rings) held, the
// tables are smooth in the parameters; they are evaluated with Jets by a
// DynamicAutoDiffCostFunction once per parameter point (CachedTables: the
// residual blocks of every chunk of rows ask for the same point), and
// reach the rows' residuals through DynamicCostFunctionToFunctor, which
// applies the chain rule. Includes Ceres: for fitting/*.cc only.
#pragma once

#include <ceres/ceres.h>
#include <ceres/dynamic_cost_function_to_functor.h>

#include <memory>
#include <mutex>
#include <type_traits>
#include <utility>
#include <vector>

#include "fitting/flatten_internal.h"
#include "models/energy_bound.h"
#include "models/math.h"

namespace clothfit {

// The tables of `plan` from the blocks: light then view, kEnergyBoundNodes
// each. The evaluator supplies BoundRho(blocks), a callable rho(wi, wo)
// giving the paper's model's cosine-weighted value without the scale; the
// scale block (index into the blocks, or -1) enters as max(1, scale), as
// in models/bounded.h. At each parameter point the plan's derived entries
// are first refined to their crests there (Refine, RefineEnergyBoundPlan),
// so that they follow peaks the parameters move.
template <class Evaluator>
class BoundTablesFunctor {
 public:
  BoundTablesFunctor(std::shared_ptr<const Evaluator> evaluator,
                     EnergyBoundPlan plan, int scale_block)
      : evaluator_(std::move(evaluator)),
        base_(std::move(plan)),
        plan_(base_),
        scale_block_(scale_block) {}

  // The plan refined at the point `blocks` (doubles), for the evaluations
  // at that point that follow.
  void Refine(const double* const* blocks) const {
    plan_ = RefineEnergyBoundPlan(Rho(blocks), base_);
  }

  // With Jets, the held entries of the plan are the values given by
  // SetHeld (the tables in double at the same point), without derivative.
  // Flattened as the rows' residuals are (fitting/flatten_internal.h): the
  // tables' quadratures are most of a bounded solve's time, and without it
  // GCC leaves Eigen's per-lane Jet products as calls.
  template <typename T>
  CLOTHFIT_FLATTEN bool operator()(const T* const* blocks, T* tables) const {
    const int n = static_cast<int>(plan_.light.size());
    const bool jets = !std::is_same_v<T, double>;
    EnergyBoundTables<T>(plan_, Rho(blocks), tables, tables + n,
                         jets ? held_.data() : nullptr);
    return true;
  }

  void SetHeld(std::vector<double> held) const { held_ = std::move(held); }

 private:
  // The model at the blocks, its scale max(1, scale).
  template <typename T>
  auto Rho(const T* const* blocks) const {
    const T s =
        scale_block_ >= 0 ? Max(T(1.0), blocks[scale_block_][0]) : T(1.0);
    return [rho = evaluator_->BoundRho(blocks), s](const glm::dvec3& wi,
                                                   const glm::dvec3& wo) {
      return rho(wi, wo) * s;
    };
  }

  std::shared_ptr<const Evaluator> evaluator_;
  EnergyBoundPlan base_;
  // base_ refined at the last point; CachedTables sets it (Refine) and
  // held_ under its lock.
  mutable EnergyBoundPlan plan_;
  int scale_block_;
  mutable std::vector<double> held_;
};

// Whether an evaluator supplies BoundRho (the thread and cloth fits).
template <class E, class = void>
struct HasBoundRho : std::false_type {};
template <class E>
struct HasBoundRho<E, std::void_t<decltype(std::declval<const E&>().BoundRho(
                          std::declval<const double* const*>()))>>
    : std::true_type {};

// The tables as a cost function that remembers its last point: values,
// and the Jacobians once asked for, which are computed after the values
// (the functor's held entries take those). Thread-safe (Ceres evaluates
// residual blocks in parallel).
template <class Functor, class Inner>
class CachedTables : public ceres::CostFunction {
 public:
  CachedTables(const Functor* functor, std::unique_ptr<Inner> inner)
      : functor_(functor), inner_(std::move(inner)) {
    *mutable_parameter_block_sizes() = inner_->parameter_block_sizes();
    set_num_residuals(inner_->num_residuals());
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const std::vector<int32_t>& sizes = parameter_block_sizes();
    std::vector<double> key;
    for (size_t b = 0; b < sizes.size(); ++b) {
      key.insert(key.end(), parameters[b], parameters[b] + sizes[b]);
    }
    const int m = num_residuals();
    std::lock_guard<std::mutex> lock(mutex_);
    if (key != key_) {
      values_.assign(m, 0.0);
      has_jacobian_ = false;
      functor_->Refine(parameters);
      if (!inner_->Evaluate(parameters, values_.data(), nullptr)) {
        key_.clear();
        return false;
      }
      key_ = std::move(key);
    }
    std::copy(values_.begin(), values_.end(), residuals);
    if (jacobians == nullptr) return true;
    if (!has_jacobian_) {
      jacobian_.assign(m * key_.size(), 0.0);
      std::vector<double*> blocks;
      size_t offset = 0;
      for (int32_t size : sizes) {
        blocks.push_back(jacobian_.data() + offset);
        offset += static_cast<size_t>(m) * size;
      }
      functor_->SetHeld(values_);
      std::vector<double> values(m);
      if (!inner_->Evaluate(parameters, values.data(), blocks.data())) {
        return false;
      }
      has_jacobian_ = true;
    }
    size_t offset = 0;
    for (size_t b = 0; b < sizes.size(); ++b) {
      const size_t count = static_cast<size_t>(m) * sizes[b];
      if (jacobians[b] != nullptr) {
        std::copy(jacobian_.begin() + offset,
                  jacobian_.begin() + offset + count, jacobians[b]);
      }
      offset += count;
    }
    return true;
  }

 private:
  const Functor* functor_;  // owned by inner_
  std::unique_ptr<Inner> inner_;
  mutable std::mutex mutex_;
  mutable std::vector<double> key_, values_, jacobian_;
  mutable bool has_jacobian_ = false;
};

// The bound's tables of an evaluator's model through `plan`, over the
// blocks of the given sizes (those a fit's residuals use): call with
// double or Jet blocks, writing 2 kEnergyBoundNodes values.
using BoundTables = ceres::DynamicCostFunctionToFunctor;

template <class Evaluator>
std::shared_ptr<const BoundTables> MakeBoundTables(
    std::shared_ptr<const Evaluator> evaluator, const EnergyBoundPlan& plan,
    const std::vector<int>& block_sizes, int scale_block) {
  using Functor = BoundTablesFunctor<Evaluator>;
  // Derivative lanes per pass: a cloth's free parameters in one or two
  // passes (each pass evaluates the model's values again).
  using Cost = ceres::DynamicAutoDiffCostFunction<Functor, 16>;
  auto* functor = new Functor(std::move(evaluator), plan, scale_block);
  auto cost = std::make_unique<Cost>(functor);
  for (int size : block_sizes) cost->AddParameterBlock(size);
  cost->SetNumResiduals(static_cast<int>(plan.light.size() + plan.view.size()));
  return std::make_shared<const BoundTables>(
      new CachedTables<Functor, Cost>(functor, std::move(cost)));
}

}  // namespace clothfit
