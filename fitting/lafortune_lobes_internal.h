// The Lafortune fits' lobe solve with the lookup table fixed (Daubert et
// al. 2001, Section 5: the lobes by Levenberg-Marquardt, eq. 3 with T
// held): every channel of a texel's lobes on its samples. For
// fitting/lafortune_fit.cc only.
#pragma once

#include <vector>

#include "fitting/lafortune_fit.h"

namespace clothfit {

// Fits all three channels' lobes of *p on `samples` with the table T
// fixed at t (per view). first_pass: from a far start (the paper's or a
// given one), which runs Ceres' projected line search and, with
// options.warm_channels, starts channels 1 and 2 from channel 0's
// solution. The lobes stay within their reach at most peak_cap
// (fitting/lafortune_bounds_internal.h). Returns the solver's iterations.
int FitLobes(const TexelSamples& samples, const std::vector<glm::dvec3>& t,
             const LafortuneFitOptions& options, bool first_pass,
             double peak_cap, LafortuneParams* p);

}  // namespace clothfit
