// Least-squares problems of a few unknowns (the linear entries of a start
// search, fitting/start_search.h), solved without allocation. Internal to
// fitting/.
#pragma once

namespace clothfit {

// The most unknowns these solve.
inline constexpr int kMaxSmallSystem = 8;

// Solves the m x m symmetric system a x = b (row-major, m <=
// kMaxSmallSystem) by Cholesky; false where a is not positive definite to
// working precision (a column without effect), x then undefined.
bool SolveCholesky(const double* a, const double* b, int m, double* x);

// min 1/2 x^T G x - b^T x over x >= lo, entry by entry (G m x m row-major,
// m <= kMaxSmallSystem, positive definite on every subset of the entries):
// the active-set method of Lawson and Hanson (1974, "Solving Least Squares
// Problems", ch. 23) on x - lo >= 0. False where a subset's system is not
// positive definite.
bool SolveAboveBounds(const double* g, const double* b, const double* lo, int m,
                      double* x);

}  // namespace clothfit
