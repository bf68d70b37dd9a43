// CLOTHFIT_FLATTEN: on a residual functor's templated operator(), inlines
// everything it calls (CLOTHFIT_INLINE_ALL of models/math.h, off under the
// sanitizers). With the dynamic-size Jets of ModelResidual
// (fitting/model_residual_internal.h), GCC otherwise leaves Eigen's
// per-lane Jet products as calls in the innermost loop (a thread fit ran
// 2.2-2.6x slower; the Lafortune residuals' fixed-size Jets gained
// nothing measurable). Internal to fitting/.
#pragma once

#include "models/math.h"

#define CLOTHFIT_FLATTEN CLOTHFIT_INLINE_ALL
