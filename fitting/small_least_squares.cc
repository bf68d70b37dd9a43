#include "fitting/small_least_squares.h"

#include <algorithm>
#include <cmath>

namespace clothfit {

bool SolveCholesky(const double* a_in, const double* b_in, int m, double* x) {
  double a[kMaxSmallSystem * kMaxSmallSystem];
  std::copy(a_in, a_in + m * m, a);
  std::copy(b_in, b_in + m, x);
  for (int j = 0; j < m; ++j) {
    double d = a[j * m + j];
    for (int k = 0; k < j; ++k) d -= a[j * m + k] * a[j * m + k];
    if (!(d > 1e-12 * std::abs(a[j * m + j])) || !(d > 0.0)) return false;
    const double l = std::sqrt(d);
    a[j * m + j] = l;
    for (int i = j + 1; i < m; ++i) {
      double v = a[i * m + j];
      for (int k = 0; k < j; ++k) v -= a[i * m + k] * a[j * m + k];
      a[i * m + j] = v / l;
    }
  }
  for (int i = 0; i < m; ++i) {  // L y = b
    for (int k = 0; k < i; ++k) x[i] -= a[i * m + k] * x[k];
    x[i] /= a[i * m + i];
  }
  for (int i = m - 1; i >= 0; --i) {  // L^T x = y
    for (int k = i + 1; k < m; ++k) x[i] -= a[k * m + i] * x[k];
    x[i] /= a[i * m + i];
  }
  return true;
}

bool SolveAboveBounds(const double* g, const double* b_in, const double* lo,
                      int m, double* x) {
  double b[kMaxSmallSystem];  // the problem in y = x - lo >= 0
  double scale = 0.0;
  for (int i = 0; i < m; ++i) {
    b[i] = b_in[i];
    for (int k = 0; k < m; ++k) b[i] -= g[i * m + k] * lo[k];
    scale = std::max(scale, std::abs(b[i]));
  }
  double y[kMaxSmallSystem] = {};
  bool passive[kMaxSmallSystem] = {};
  for (int outer = 0; outer < 3 * m + 3; ++outer) {
    // The entry at its bound whose gradient most wants it to grow.
    int enter = -1;
    double best = 1e-13 * scale;
    for (int i = 0; i < m; ++i) {
      if (passive[i]) continue;
      double w = b[i];
      for (int k = 0; k < m; ++k) w -= g[i * m + k] * y[k];
      if (w > best) best = w, enter = i;
    }
    if (enter < 0) break;
    passive[enter] = true;
    for (int inner = 0; inner <= m; ++inner) {
      int index[kMaxSmallSystem], p = 0;
      for (int i = 0; i < m; ++i) {
        if (passive[i]) index[p++] = i;
      }
      double gp[kMaxSmallSystem * kMaxSmallSystem], bp[kMaxSmallSystem],
          z[kMaxSmallSystem];
      for (int u = 0; u < p; ++u) {
        bp[u] = b[index[u]];
        for (int v = 0; v < p; ++v) gp[u * p + v] = g[index[u] * m + index[v]];
      }
      if (!SolveCholesky(gp, bp, p, z)) return false;
      // Step toward z as far as every entry stays >= 0; an entry that
      // stops the step returns to its bound.
      double alpha = 1.0;
      int block = -1;
      for (int u = 0; u < p; ++u) {
        const double yi = y[index[u]];
        if (z[u] > 0.0) continue;
        const double ratio = yi / (yi - z[u]);
        if (ratio < alpha) alpha = ratio, block = index[u];
      }
      for (int u = 0; u < p; ++u) {
        y[index[u]] += alpha * (z[u] - y[index[u]]);
      }
      if (block < 0) break;
      for (int u = 0; u < p; ++u) {
        if (index[u] == block || y[index[u]] <= 0.0) {
          y[index[u]] = 0.0;
          passive[index[u]] = false;
        }
      }
    }
  }
  for (int i = 0; i < m; ++i) x[i] = lo[i] + std::max(y[i], 0.0);
  return true;
}

}  // namespace clothfit
