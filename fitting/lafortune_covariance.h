// Standard deviations of a Lafortune fit's diffuse and lobe entries
// (Daubert et al. 2001, eq. 2-3), at the gauge the fit reports: the
// lookup table and the lobes trade a common scale per channel (T / s
// times f1 with rho_d s and C s^(1/N) is the same model), so the table's
// mean over its fitted views is held at its value (1 after the joint
// solve's normalisation) and the entries' covariance is that of the
// solution under that constraint.
#pragma once

#include <vector>

#include "fitting/fit_result.h"
#include "fitting/lafortune_samples.h"
#include "models/lafortune.h"

namespace clothfit {

// Sets the stddev (and, with the noise level estimated - sigma_known
// false - the sandwich estimate) of each entry of report->parameters
// named as LafortuneParameterReports names them ("diffuse_r",
// "lobes[1].N_b"), from the Jacobian of the samples' weighted residuals
// with respect to the channel's entries and the fitted views' T (`own`:
// the views with an entry of their own; the others follow them by the
// table's interpolation, models/lafortune.h LookupView). Channels are
// independent problems; with the level estimated its variance is each
// channel's 2 cost / dof. Where the data do not determine some entries (a
// collapsed lobe) or views' T, report->identifiability names them; they
// get none, and the others' are conditional (held at their values,
// report->stddev_conditional; fitting/covariance_internal.h). None at
// all, report->identifiability saying why, when the model is not the
// least-squares solution (scaled to conserve energy, or a view's T
// lowered to the energy bound) or when the dense Jacobian would exceed
// 1e7 entries (samples x parameters of a channel).
void ReportLafortuneStddev(const TexelSamples& samples,
                           const LafortuneModel& model,
                           const std::vector<bool>& own, bool sigma_known,
                           FitReport* report);

}  // namespace clothfit
