// The shared Ceres machinery of the fits: one flat parameter vector split
// into blocks, bounds from the models' parameter tables, free/fixed
// entries, robust loss, multi-start, and the covariance-based report. Each
// model's fit supplies an evaluator for the one residual
// (fitting/model_residual_internal.h); Eigen and Ceres stay inside
// fitting/*.cc.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "fitting/fit_result.h"
#include "models/params.h"

namespace ceres {
class LossFunction;
class Problem;
}  // namespace ceres

namespace clothfit {

// One parameter of the flat vector.
struct ParameterSpec {
  std::string name;
  double lower = 0.0, upper = 0.0;
  bool free = true;
  // The bounds are the parameter's physical range (kd in [0, 1], albedo >=
  // 0): a solution on them is legitimate. Otherwise they only limit the
  // search (eta, the widths, the scale), and a free parameter that ends on
  // one means the solver left the region where the model is meaningful:
  // the fit is reported as not converged.
  bool physical_bounds = false;
  // Each end on its own: physical_bounds, or the end is a closed end of
  // the parameter's documented range (a width's 90 degrees, the flattest
  // lobe the model defines; its open end 0 is not, and the search stops
  // at 0.2).
  bool physical_lower = false, physical_upper = false;
};

// The spec of a table entry: its fit bounds, free.
inline ParameterSpec SpecOf(const ParamInfo& info, const std::string& name) {
  ParameterSpec spec{name, info.fit_lo, info.fit_hi, true, info.physical};
  spec.physical_lower =
      info.physical || (info.fit_lo == info.valid.lo && !info.valid.lo_open);
  spec.physical_upper =
      info.physical || (info.fit_hi == info.valid.hi && !info.valid.hi_open);
  return spec;
}

// One spec per flat entry of p (models/params.h ToArray), named `prefix`
// + the entry's name ("threads[0].albedo_r").
template <typename P>
std::vector<ParameterSpec> ParameterSpecs(const P& p,
                                          const std::string& prefix = "") {
  std::vector<ParameterSpec> specs;
  for (const FlatEntry& e : FlatEntries(p)) {
    specs.push_back(SpecOf(*e.info, prefix + e.Name()));
  }
  return specs;
}

// The factor on the whole model (models/params.h kModelScale).
inline constexpr const ParamInfo& kFitScale = kModelScale;

// One prediction of LeastSquaresProblem::predict.
using PredictionVisitor =
    std::function<void(double model, double measured, const TableRow* row)>;

// Which rows LeastSquaresProblem::add_residuals adds, and how.
struct ResidualRows {
  // Ascending row indices; null: every row.
  const std::vector<uint32_t>* subset = nullptr;
  // Chunks of rows as one residual block each, the triangular factor R of
  // the QR decomposition of the chunk's [J | r] (n + 1 residuals for n
  // parameters): R^T R = [J r]^T [J r], so the cost, the gradient J^T r
  // and the Gauss-Newton matrix J^T J, hence every step of the solver, are
  // those of the rows themselves, while the solver holds n + 1 residuals
  // per chunk instead of one per row. false: the chunks' rows as they are.
  // A robust loss, which acts on each row, gets one block per row.
  bool compress = true;
};

// A problem over the blocks of `x`: block b holds x[offset_b, offset_b +
// size_b). `add_residuals` adds the residual blocks to `problem`, given the
// block pointers (into the x being solved).
struct LeastSquaresProblem {
  std::vector<ParameterSpec> specs;  // one per entry of x
  std::vector<int> block_sizes;      // sum = specs.size()
  // Residuals are (model - measured) / sigma with sigma known in data
  // units (Weighting::LevelKnown); false: sigma is known up to its level F
  // (weights of F = 1), the covariance is scaled by the residual variance
  // 2 cost / (residuals - free parameters), and the report also gives the
  // sandwich estimate.
  bool sigma_known = true;
  // The number of rows add_residuals knows (0: it does not subsample, and
  // every solve sees every row).
  size_t rows = 0;
  // Adds the residual blocks of `which` rows (ResidualRows); `loss` (may be
  // null) goes to each row. Returns the number of residuals of those rows
  // (not of the blocks, which compression makes fewer).
  std::function<size_t(const std::vector<double*>& blocks,
                       ceres::LossFunction* loss, ceres::Problem* problem,
                       const ResidualRows& which)>
      add_residuals;
  // Model values and the data, in data units, for rms errors and for
  // naming the row of a non-finite value: called with a solution or a
  // start; calls `visit` with each pair (model, measured) and its table row,
  // rows and channels in order (nothing is held for all rows).
  std::function<void(const std::vector<double>& x,
                     const PredictionVisitor& visit)>
      predict;
  // If set: the table row of row i of add_residuals (i < rows), for
  // checks that need the rows and not the model (DistinctResiduals).
  std::function<const TableRow*(size_t i)> row;
  // If set (weights that depend on the model's value, relative noise):
  // recomputes the residuals' weights at x; the solver then solves again
  // from the best solution until the weights settle.
  std::function<void(const std::vector<double>& x)> reweight;
  // If set: the solver's x is not what is reported (a reparameterisation,
  // e.g. coverages that sum to at most 1, fitting/cloth_fit.cc); the
  // report gives reported(x) (same size and names as specs) and its
  // standard deviations by the delta method, G Cov G^T with G = d
  // reported / dx over the free entries (central differences).
  std::function<std::vector<double>(const std::vector<double>& x)> reported;
  // If set: whether solution x is plausible as it would be written (a
  // cloth that conserves energy, fitting/cloth_fit.cc). The multi-start
  // then keeps a plausible solution over any implausible one (the lowest
  // cost within each kind), and the stopping rule counts solves of the
  // kept one's kind.
  std::function<bool(const std::vector<double>& x)> plausible;
  // Multi-start stopping rule: when > 0, the starts (ranked best first by
  // their caller) are solved in order until the lowest final cost so far
  // has been reached by this many solves (costs within a relative 1e-3 of
  // it: the same basin), and the rest are skipped. FitReport::starts
  // counts the solves run and FitReport::search says how the rule ended.
  int stop_after_hits = 0;
  // Screening many starts: when screen_keep > 0 and there are more starts
  // than that, each start is first solved for at most screen_iterations
  // iterations, and the best screen_keep of those solutions (plausible
  // ones first, each kind by cost) are solved on from where they stopped,
  // in that order (the stopping rule then counts those solves). A basin is
  // told from a few iterations, and most starts are far from the best:
  // fitting/cloth_fit.h.
  int screen_iterations = 0;
  int screen_keep = 0;
};

// Problems of more rows than this solve their starts (and their
// reweighting passes) on a sample of kSampleRows rows (SampleRows), and
// then refine the best on every row; the start searches of the thread and
// cloth fits work on the same sample.
inline constexpr size_t kSampleRows = 20000;

// `m` of the indices 0 .. n-1, ascending, spread at random with a fixed
// seed (selection sampling, Knuth's Algorithm S): no row order aliases
// with it, as an even stride would with a table's direction grid. All of
// them when m >= n.
std::vector<uint32_t> SampleRows(size_t n, size_t m);

// Solves from each start in `starts` (each a full x), keeps the lowest cost,
// and reports on it; *x receives the best solution. options.progress (if
// set) is told "start i of n" as it goes. With lsq.rows > kSampleRows the
// starts are solved on SampleRows(lsq.rows, kSampleRows) and the best is
// solved again on every row: the report (cost, residuals, covariance) is
// that of every row.
FitReport SolveLeastSquares(const LeastSquaresProblem& problem,
                            const std::vector<std::vector<double>>& starts,
                            const SolverOptions& options,
                            std::vector<double>* x);

// Marks entries fixed/free. A name matches an entry by its full name
// ("threads[0].kd"), by its last part ("kd": every thread), and "albedo"
// matches the three albedo_r/g/b. `free_only`, when not empty, fixes every
// entry it does not match; `fix` then fixes what it matches. Throws
// InputError naming `option` and the name when a name matches nothing, when
// a name is in both lists, and when they leave no entry free.
void ApplyFreeFix(const std::vector<std::string>& fix,
                  const std::vector<std::string>& free_only,
                  std::vector<ParameterSpec>* specs);

// Frees the entries `names` match (as ApplyFreeFix's), on top of the
// free set; throws InputError naming --also-free for a name matching
// nothing.
void FreeAlso(const std::vector<std::string>& names,
              std::vector<ParameterSpec>* specs);

// The first pair of `lsq.predict` at x whose model value, or its
// difference from the data, is not finite, named by its table line,
// directions and the parameters; "" when every value is finite.
std::string NonFiniteRow(const LeastSquaresProblem& lsq,
                         const std::vector<double>& x);

// How many of the `residuals` are distinct at x: residuals of rows that
// repeat one measurement (the same directions, texel and normal) count
// once, as they cannot determine more than one row does. Stops counting
// (returns `residuals`) once `enough` distinct rows are seen.
int DistinctResiduals(const LeastSquaresProblem& lsq,
                      const std::vector<double>& x, int residuals, int enough);

}  // namespace clothfit
