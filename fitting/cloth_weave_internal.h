// The cloth fit's parameter vector and the weave it describes, shared by
// the fit (fitting/cloth_fit.cc) and its start search
// (fitting/cloth_search.cc). Internal to fitting/.
//
// The flat vector: per thread j, the thread's table (kThreadFlatSize
// entries, models/microcylinder_thread.h), then its weave entries
// [coverage, offset_scale, offsets_deg[0], ..., offsets_deg[K_j - 1]]
// (thread j's k-th tangent offset is offset_scale * offsets_deg[k]); then
// the cloth's [rotation_deg, diffuse_r, diffuse_g, diffuse_b]; then the
// scale. Ceres sees the same blocks: two per thread, the cloth's, the
// scale's.
#pragma once

#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include "fitting/least_squares.h"
#include "io/table.h"
#include "models/evaluate.h"
#include "models/microcylinder_cloth.h"
#include "models/prepared.h"

namespace clothfit {

class ClothVector {
 public:
  static constexpr int kClothBlockSize = 4;  // rotation, diffuse rgb

  explicit ClothVector(const ClothParams& layout);

  size_t Threads() const { return start_.size(); }
  size_t Thread(size_t j) const { return start_[j]; }  // its table's first
  size_t Coverage(size_t j) const { return start_[j] + kThreadFlatSize; }
  size_t OffsetScale(size_t j) const { return Coverage(j) + 1; }
  size_t Offset(size_t j, size_t k) const { return Coverage(j) + 2 + k; }
  size_t Offsets(size_t j) const { return samples_[j]; }
  size_t Rotation() const { return cloth_; }
  size_t Diffuse(int c) const { return cloth_ + 1 + c; }
  size_t Scale() const { return cloth_ + kClothBlockSize; }
  size_t size() const { return Scale() + 1; }
  // Ceres blocks: [thread j], [weave j] per thread, [cloth], [scale].
  std::vector<int> BlockSizes() const;
  int ClothBlock() const { return static_cast<int>(2 * Threads()); }
  int ScaleBlock() const { return ClothBlock() + 1; }

 private:
  std::vector<size_t> start_, samples_;
  size_t cloth_ = 0;
};

// What stays fixed through a fit, shared by all residuals.
struct Weave {
  explicit Weave(const ClothParams& l) : layout(l), vector(l) {}
  ClothParams layout;  // directions, base offsets, fixed values
  ClothVector vector;
  bool shared_albedo = false;  // every thread uses thread 0's albedo
  // Free coverages that sum to at most 1, by stick-breaking (the threads
  // s_0, s_1, ... in order): the solver's entry u_k in [0, 1] gives
  // a_{s_k} = R u_k prod_{i<k} (1 - u_i), R = 1 - the fixed coverages'
  // sum (at least 0). Box bounds on u, no clipping of a; empty: no
  // coverage is free.
  std::vector<size_t> stick;
  double remaining = 1.0;
};

// The coverages a of the stick-breaking entries u (Weave::stick), in any
// scalar type: `coverage(j)` reads and writes thread j's entry.
template <typename T, typename Coverage>
void StickToCoverage(const Weave& weave, const Coverage& coverage) {
  T left(weave.remaining);
  for (size_t j : weave.stick) {
    T& entry = coverage(j);
    const T u = entry;
    entry = left * u;
    left = left * (T(1.0) - u);
  }
}

// A solver vector as the parameters it stands for (stick entries as
// coverages, the rotation in (-180, 180]): what the report and the
// parameter file give. CoverageToStick is the inverse for the coverages (a
// start's coverages as stick entries, moved into [0, 1]).
std::vector<double> ReportedVector(const Weave& weave, std::vector<double> x);
std::vector<double> CoverageToStick(const Weave& weave, std::vector<double> x);

// The flat vector of c (whose threads have the layout's sample counts):
// offset_scale 1, scale 1; and the cloth of a reported vector.
std::vector<double> ClothToVector(const ClothParams& c);
ClothParams ClothFromVector(const Weave& weave, const std::vector<double>& x);

// The fit's parameter specs in vector order, with the default free set:
// per thread kd, gamma_s_deg, gamma_v_deg, albedo.
std::vector<ParameterSpec> ClothSpecs(const ClothParams& layout);

// The tangent samples of one row for a fixed weave (directions, rotation,
// offsets); with eta fixed (eta_fixed[j]), their Fresnel terms too. Then
// only the parameter-dependent part of the thread BSDF needs Jets.
struct RowSamples {
  std::vector<std::vector<TangentSample<double>>> per_thread;
  // per_thread[j][k]'s Fresnel term; empty for a thread whose eta is free.
  std::vector<std::vector<double>> fresnel;

  int Count(size_t j) const { return static_cast<int>(per_thread[j].size()); }
  int Total(size_t j) const { return Count(j); }
  const TangentSample<double>& Get(size_t j, int k) const {
    return per_thread[j][k];
  }
  template <typename T>
  ThreadLobes<T> Lobes(size_t j, int k, const TangentSample<double>& sample,
                       const ThreadLobeParams<T>& params) const {
    if (fresnel[j].empty()) return ThreadLobesOf(sample.geometry, params);
    return ThreadLobesGivenFresnel(sample.geometry, fresnel[j][k], params);
  }
};

RowSamples ComputeRowSamples(const ClothParams& cloth,
                             const std::vector<bool>& eta_fixed,
                             const TableRow& row);
// The same into *out, reusing its vectors' storage.
void FillRowSamples(const ClothParams& cloth,
                    const std::vector<bool>& eta_fixed, const TableRow& row,
                    RowSamples* out);

// The cloth described by Ceres' blocks (ClothVector's order, without the
// scale); with_geometry: the tangent offsets and rotation too (otherwise
// they are the layout's, which made the precomputed samples).
template <typename T>
ClothParamsT<T> ClothFromBlocks(const Weave& weave, const T* const* blocks,
                                bool with_geometry) {
  const size_t n = weave.layout.threads.size();
  ClothParamsT<T> c;
  c.threads.resize(n);
  for (size_t j = 0; j < n; ++j) {
    const ClothThread& base = weave.layout.threads[j];
    ClothThreadT<T>& th = c.threads[j];
    th.direction = base.direction;
    FromArray(blocks[2 * j], &th.params);
    if (weave.shared_albedo) {
      th.params.albedo = Vec3<T>(blocks[0][4], blocks[0][5], blocks[0][6]);
    }
    const T* w = blocks[2 * j + 1];
    th.coverage = w[0];
    if (with_geometry) {
      th.offsets_deg.resize(base.offsets_deg.size());
      for (size_t k = 0; k < base.offsets_deg.size(); ++k) {
        th.offsets_deg[k] = w[1] * w[2 + k];
      }
    }
  }
  const T* cloth = blocks[2 * n];
  c.rotation_deg = with_geometry ? cloth[0] : T(weave.layout.rotation_deg);
  c.diffuse = Vec3<T>(cloth[1], cloth[2], cloth[3]);
  StickToCoverage<T>(weave,
                     [&](size_t j) -> T& { return c.threads[j].coverage; });
  return c;
}

// The cloth's value at row i (without the scale, which ModelResidual
// applies). With the geometry fixed the row's tangent samples were
// computed once (`samples`); otherwise they follow the blocks.
struct ClothEvaluator {
  const MeasurementTable* table;
  std::shared_ptr<const Weave> weave;
  std::vector<std::shared_ptr<const RowSamples>> samples;  // per row, or null
  // The geometry (rotation, offsets) fixed, and which etas are: the
  // tangent samples of the weave's layout, held per row (`samples`) or,
  // for more rows than ClothFitOptions::held_sample_rows, computed per row.
  bool geometry_fixed = false;
  std::vector<bool> eta_fixed;
  // The rows' energy bound factors (fitting/energy_bound_fit_internal.h),
  // or null: the paper's model.
  const std::vector<double>* bound_factor = nullptr;

  template <typename T>
  Vec3<T> operator()(const T* const* blocks, size_t i) const {
    const TableRow& row = table->rows[i];
    const T factor(bound_factor ? (*bound_factor)[i] : 1.0);
    if (geometry_fixed) {
      const ClothParamsT<T> c = ClothFromBlocks(*weave, blocks, false);
      return ConvertQuantity(
                 samples.empty()
                     ? RhoFromSamplesNow(c, row)
                     : ClothRhoFromSamples(c, *samples[i], row.wi.z),
                 Quantity::kCosineWeighted, table->quantity, row.wi.z) *
             factor;
    }
    return Value(ClothFromBlocks(*weave, blocks, true), row.wi, row.wo,
                 table->quantity) *
           factor;
  }

  // The paper's cloth at the blocks, rho(wi, wo) cosine-weighted without
  // the scale: what the energy bound is a quadrature of. In double with
  // its sample frames computed once (models/prepared.h); in Jets with the
  // geometry fixed, each direction pair's tangent samples (and the fixed
  // etas' Fresnel terms) in double and only the lobes in Jets, as the
  // rows' (RowSamples), the same value: the quadratures' directions are
  // fixed numbers.
  template <typename T>
  auto BoundRho(const T* const* blocks) const {
    if constexpr (std::is_same_v<T, double>) {
      return [c = PrepareCloth<double>(ClothFromBlocks(*weave, blocks, true))](
                 const glm::dvec3& wi, const glm::dvec3& wo) {
        return Rho(c, wi, wo);
      };
    } else {
      return [c = ClothFromBlocks(*weave, blocks, !geometry_fixed), this](
                 const glm::dvec3& wi, const glm::dvec3& wo) {
        if (!geometry_fixed) return Rho(c, wi, wo);
        thread_local TableRow row;
        row.wi = wi;
        row.wo = wo;
        return RhoFromSamplesNow(c, row);
      };
    }
  }

  // rho of c (its geometry the layout's, fixed) at the row's directions,
  // from the row's tangent samples computed now.
  template <typename T>
  Vec3<T> RhoFromSamplesNow(const ClothParamsT<T>& c,
                            const TableRow& row) const {
    thread_local RowSamples scratch;
    FillRowSamples(weave->layout, eta_fixed, row, &scratch);
    return ClothRhoFromSamples(c, scratch, row.wi.z);
  }
};

}  // namespace clothfit
