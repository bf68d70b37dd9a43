// CLOTHFIT_FLATTEN: on a residual functor's templated operator(), inlines
// everything it calls. With the dynamic-size Jets of ModelResidual
// (fitting/model_residual_internal.h), GCC otherwise leaves Eigen's
// per-lane Jet products as calls in the innermost loop (a thread fit ran
// 2.2-2.6x slower; the Lafortune residuals' fixed-size Jets gained
// nothing measurable). Off under the sanitizers: with their
// instrumentation inlined too, GCC compiled cloth_fit.cc for over 8
// minutes and 5 GB without finishing. Internal to fitting/.
#pragma once

#if defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(memory_sanitizer) || \
    __has_feature(thread_sanitizer)
#define CLOTHFIT_NO_FLATTEN
#endif
#endif
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define CLOTHFIT_NO_FLATTEN
#endif

#if (defined(__GNUC__) || defined(__clang__)) && !defined(CLOTHFIT_NO_FLATTEN)
#define CLOTHFIT_FLATTEN __attribute__((flatten))
#else
#define CLOTHFIT_FLATTEN
#endif
