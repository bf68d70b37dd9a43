// Fits the optically thin slab (docs/models.md; Frisvad et al.) to one or more
// tables: BSDF tables (brdf or cosine_weighted) whose rows may be reflection
// (wo on the side of wi) or transmission (far side), and direct-transmittance
// tables (quantity transmittance, D(|wo.z|) = exp(-tau/|wo.z|)). Free: tau
// (one for all channels, or one per channel on request) and the albedo per
// channel (one for one-channel tables).
//
// Besides the fit report, the result says whether the data lie within the
// model's regime (docs/slab.md, "Validity"):
//  - model error against data noise: chi^2 per degree of freedom of the
//    fit, compared with its 3-sigma upper limit 1 + 3 sqrt(2 / dof) for
//    pure noise (only when every table gives sigma);
//  - the multiple-scattering regime: the estimated error A q(tau) of the
//    single-scattering form against all orders (models/slab.h; close to
//    the Monte Carlo chart for tau <= 1) above 1 %, the accuracy the paper
//    promises. The paper's own bound, tau < 0.2, is reported as well but is
//    not enough (at tau = 0.05, A = 0.9 the error is 9 %). Where multiple
//    scattering matters the fitted albedo absorbs it; the report gives the
//    albedo corrected for it (A_fit / (1 + A_fit q));
//  - the paper's comparison: the constant-alpha baseline (a constant
//    alpha for the direct transmittance and a Lambertian BRDF, back-lit
//    either rendered as front-lit or black, the better of the two), fitted
//    in closed form to the same residuals, and how many times lower the
//    slab model's rms (normalised) error is.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "fitting/fit_result.h"
#include "io/table.h"
#include "models/slab.h"

namespace clothfit {

struct SlabFitOptions {
  SolverOptions solver;
  // Starting values: they join the start grid; fixed entries keep them
  // (SlabParams() defaults without an init).
  std::optional<SlabParams> init;
  // One tau per channel (tau_r, tau_g, tau_b) instead of one for all.
  bool per_channel_tau = false;
  // Parameter names ("tau", "tau_r", ..., "albedo", "albedo_r", ...) held
  // at their initial value; `free_only`, when not empty, frees only these.
  std::vector<std::string> fix;
  std::vector<std::string> free_only;
  // Multi-start: solve from this many of the best grid points.
  int solve_starts = 2;
};

struct SlabValidity {
  bool sigma_known = false;
  int dof = 0;                // residuals - free parameters
  double chi2_per_dof = 0.0;  // 2 cost / dof (sigma known)
  double chi2_limit = 0.0;    // 1 + 3 sqrt(2 / dof)
  bool error_exceeds_noise = false;
  double max_tau = 0.0;
  bool above_paper_tau_limit = false;  // max_tau > kSlabPaperTauLimit
  // max over channels of SlabSingleScatterError(tau, albedo), and whether
  // it exceeds kSlabRegimeTolerance.
  double estimated_model_error = 0.0;
  bool multiple_scattering = false;
  glm::dvec3 corrected_albedo{0.0};  // SlabMultipleScatteringAlbedo
  // The constant-alpha baseline and the comparison.
  std::string baseline;                       // which variant was better
  double baseline_rms = 0.0, slab_rms = 0.0;  // data units, all residuals
  double baseline_chi2_per_dof = 0.0;         // (sigma known)
  // sqrt(baseline cost / slab cost): the ratio of the rms of the
  // normalised residuals (by sigma and weight), so that f and D rows count
  // by their precision.
  double improvement = 0.0;
  bool within_regime = false;
  std::vector<std::string> notes;  // the verdicts, one sentence each
};

struct SlabFitResult : FitResult<SlabParams> {
  SlabValidity validity;
};

// Throws InputError for an empty set of tables, tables without rows, tables
// that mix one-channel and rgb values, or that mix tables with and without
// sigma, and for unknown names in fix/free_only.
SlabFitResult FitSlab(const std::vector<MeasurementTable>& tables,
                      const SlabFitOptions& options);

// The values of `p` in the order of report.parameters (names "tau",
// "tau_r", ..., "albedo", "albedo_r", ...), e.g. a column of true values.
std::vector<double> SlabValuesInReportOrder(const SlabParams& p,
                                            const FitReport& report);

// The validity report as JSON text (the "validity" entry of the "fit"
// object) and as lines for the terminal.
std::string SlabValidityJson(const SlabValidity& validity);
std::string SlabValidityText(const SlabValidity& validity);

}  // namespace clothfit
