// Lafortune lobes with a per-view lookup table (Daubert et al. 2001, eq. 1-2;
// SPEC §3.3), templated on the scalar type.
//
//   f1(l, v)    = l.z (rho_d + sum_k [Cx lx vx + Cy ly vy + Cz lz vz]^N)
//   model(l, v) = T(v) f1(l, v)                           (channel-wise)
// with [a]^N = 0 for a <= 0. l and v are unit vectors in the texel's local
// frame (normal +z, tangent +x); the model predicts the cosine-weighted
// quantity rho. A texel whose average normal n is tilted from the surface
// normal has its own frame (Section 4 of the paper): bi-normal b
// perpendicular to n and the surface's x axis, tangent t = b x n; a
// renderer rotates l and v into it (TexelFrame, ToTexelFrame). There l.z
// can be negative where the surface frame has it positive; l.z is then
// taken as 0 (a foreshortening factor cannot be negative). A specular lobe has
// Cx = Cy < 0 < Cz (the mirror of l is
// (-lx, -ly, lz)); Cx != Cy makes it anisotropic.
//
// The lookup table T(v) stores rgb and alpha for each measured view. Between
// stored views it is interpolated by Shepard's inverse-distance weighting on
// the sphere: T(v) = sum_k w_k T_k / sum_k w_k with w_k = 1 / angle(v, v_k)^3.
// This is continuous, reproduces every stored view exactly (w_k -> infinity
// as v -> v_k), and needs no triangulation of the measured views. alpha is
// not part of the product: it is the view's coverage (holes), interpolated
// the same way.
#pragma once

#include <cmath>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include "models/math.h"

namespace clothfit {

// One lobe; every entry per channel (r, g, b).
template <typename T>
struct LafortuneLobeT {
  // Weights of l_x v_x, l_y v_y, l_z v_z; unitless, any sign (Lafortune
  // et al. 1997). Eq. 2 ("C_x, C_y, C_z").
  Vec3<T> cx = Vec3<T>(T(-1.0));
  Vec3<T> cy = Vec3<T>(T(-1.0));
  Vec3<T> cz = Vec3<T>(T(1.0));
  // Exponent; unitless, > 0 (larger = narrower). Eq. 2 ("N").
  Vec3<T> n = Vec3<T>(T(10.0));
};

template <typename T>
struct LafortuneParamsT {
  // Diffuse reflectance rho_d per channel; >= 0. Eq. 2 ("rho").
  Vec3<T> diffuse = Vec3<T>(T(0.5));
  std::vector<LafortuneLobeT<T>> lobes;
};
using LafortuneLobe = LafortuneLobeT<double>;
using LafortuneParams = LafortuneParamsT<double>;

// Entries per channel of ToArray: rho_d, then Cx, Cy, Cz, N per lobe.
inline int LafortuneChannelSize(int lobes) { return 1 + 4 * lobes; }

// The parameters of one channel c as a flat array (the layout the fit
// uses): [rho_d, Cx_0, Cy_0, Cz_0, N_0, Cx_1, ...].
template <typename T>
void ToArray(const LafortuneParamsT<T>& p, int c, T* x) {
  *x++ = p.diffuse[c];
  for (const LafortuneLobeT<T>& lobe : p.lobes) {
    *x++ = lobe.cx[c];
    *x++ = lobe.cy[c];
    *x++ = lobe.cz[c];
    *x++ = lobe.n[c];
  }
}

// Inverse of ToArray for channel c of *p (which must have the lobes).
template <typename T>
void LafortuneChannelFromArray(const T* x, int c, LafortuneParamsT<T>* p) {
  p->diffuse[c] = *x++;
  for (LafortuneLobeT<T>& lobe : p->lobes) {
    lobe.cx[c] = *x++;
    lobe.cy[c] = *x++;
    lobe.cz[c] = *x++;
    lobe.n[c] = *x++;
  }
}

inline std::string ValidateLafortuneParams(const LafortuneParams& p) {
  std::ostringstream msg;
  for (int c = 0; c < 3; ++c) {
    if (!(std::isfinite(p.diffuse[c]) && p.diffuse[c] >= 0.0)) {
      msg << "diffuse: must be finite and >= 0, got " << p.diffuse[c];
      return msg.str();
    }
  }
  for (size_t k = 0; k < p.lobes.size(); ++k) {
    const LafortuneLobe& lobe = p.lobes[k];
    for (int c = 0; c < 3; ++c) {
      const std::string where = "lobes[" + std::to_string(k) + "].";
      if (!std::isfinite(lobe.cx[c]) || !std::isfinite(lobe.cy[c]) ||
          !std::isfinite(lobe.cz[c])) {
        return where + "Cx/Cy/Cz: must be finite";
      }
      if (!(std::isfinite(lobe.n[c]) && lobe.n[c] > 0.0 && lobe.n[c] <= 1e4)) {
        msg << where << "N: must be in (0, 1e4], got " << lobe.n[c];
        return msg.str();
      }
    }
  }
  return "";
}

// [a]^N: a^N for a > 0, else 0 (value and derivatives).
// For double one pow call; for Jets exp(N log a), whose derivatives are
// those of a^N (d/da = N a^(N-1), d/dN = a^N log a).
template <typename T>
T LobePower(const T& a, const T& n) {
  using std::exp;
  using std::log;
  if (!(a > T(0.0))) return T(0.0);
  if constexpr (std::is_same_v<T, double>) {
    return std::pow(a, n);
  } else {
    return exp(n * log(a));
  }
}

// f1 per channel (eq. 2). The directions' scalar type G may differ from
// the parameters' T (a fit evaluates fixed directions with Jet parameters).
template <typename T, typename G>
Vec3<T> LafortuneF1(const LafortuneParamsT<T>& p, const Vec3<G>& l,
                    const Vec3<G>& v) {
  const G xx = l.x * v.x, yy = l.y * v.y, zz = l.z * v.z;
  Vec3<T> sum = p.diffuse;
  for (const LafortuneLobeT<T>& lobe : p.lobes) {
    for (int c = 0; c < 3; ++c) {
      sum[c] += LobePower(lobe.cx[c] * xx + lobe.cy[c] * yy + lobe.cz[c] * zz,
                          lobe.n[c]);
    }
  }
  return sum * T(l.z > G(0.0) ? l.z : G(0.0));
}

// f1 of one channel only (what the per-channel fit evaluates).
template <typename T, typename G>
T LafortuneF1Channel(const T* x, int lobes, const Vec3<G>& l,
                     const Vec3<G>& v) {
  const G xx = l.x * v.x, yy = l.y * v.y, zz = l.z * v.z;
  T sum = x[0];
  for (int k = 0; k < lobes; ++k) {
    const T* lobe = x + 1 + 4 * k;
    // Products with the directions' scalars (not T(xx) * ...): a Jet times
    // a double costs a third of a Jet times a Jet.
    sum += LobePower(lobe[0] * xx + lobe[1] * yy + lobe[2] * zz, lobe[3]);
  }
  return sum * (l.z > G(0.0) ? l.z : G(0.0));
}

// A texel's local frame: tangent, bi-normal, normal (unit, right-handed).
struct TexelFrame {
  glm::dvec3 t{1.0, 0.0, 0.0}, b{0.0, 1.0, 0.0}, n{0.0, 0.0, 1.0};
};

// The frame of a texel with average normal `normal` (Daubert et al. 2001,
// Section 4): b is perpendicular to the normal and the x axis, t = b x n;
// the normal +z gives the surface frame itself. A normal along +-x (never
// above a surface) takes b = +y.
inline TexelFrame MakeTexelFrame(const glm::dvec3& normal) {
  TexelFrame f;
  const double len = glm::length(normal);
  if (!(len > 0.0) || !std::isfinite(len)) return f;
  f.n = normal / len;
  glm::dvec3 b = glm::cross(f.n, glm::dvec3(1.0, 0.0, 0.0));
  const double b_len = glm::length(b);
  b = b_len > 1e-12 ? b / b_len : glm::dvec3(0.0, 1.0, 0.0);
  f.b = b;
  f.t = glm::cross(b, f.n);
  return f;
}

// w (in the surface frame) in the texel's frame.
inline glm::dvec3 ToTexelFrame(const TexelFrame& f, const glm::dvec3& w) {
  return glm::dvec3(glm::dot(w, f.t), glm::dot(w, f.b), glm::dot(w, f.n));
}

// The per-view lookup table T(v): stored views (unit vectors in the local
// frame) with rgb and alpha. Empty = T(v) = 1, alpha 1.
struct ViewTable {
  std::vector<glm::dvec3> views;
  std::vector<glm::dvec3> color;
  std::vector<double> alpha;
};

// Shepard interpolation at v: rgb in .x/.y/.z (as glm::dvec3) and alpha.
struct ViewTableValue {
  glm::dvec3 color{1.0};
  double alpha = 1.0;
};

inline ViewTableValue LookupView(const ViewTable& table, const glm::dvec3& v) {
  ViewTableValue out;
  if (table.views.empty()) return out;
  glm::dvec3 color(0.0);
  double alpha = 0.0, total = 0.0;
  for (size_t k = 0; k < table.views.size(); ++k) {
    const glm::dvec3& u = table.views[k];
    const double d = AngleBetween(u, v, glm::length(u) * glm::length(v));
    if (d < 1e-12) {  // a stored view: exactly its entry
      out.color = table.color[k];
      out.alpha = table.alpha[k];
      return out;
    }
    const double w = 1.0 / (d * d * d);
    color += w * table.color[k];
    alpha += w * table.alpha[k];
    total += w;
  }
  out.color = color / total;
  out.alpha = alpha / total;
  return out;
}

inline std::string ValidateViewTable(const ViewTable& t) {
  if (t.color.size() != t.views.size() || t.alpha.size() != t.views.size()) {
    return "lut: views, color and alpha need the same number of entries";
  }
  for (size_t k = 0; k < t.views.size(); ++k) {
    const double len = glm::length(t.views[k]);
    if (!(std::isfinite(len) && len > 0.0)) {
      return "lut.views[" + std::to_string(k) + "]: must be a non-zero vector";
    }
    for (int c = 0; c < 3; ++c) {
      if (!std::isfinite(t.color[k][c])) {
        return "lut.color[" + std::to_string(k) + "]: must be finite";
      }
    }
    if (!(t.alpha[k] >= 0.0 && t.alpha[k] <= 1.0)) {
      return "lut.alpha[" + std::to_string(k) + "]: must be in [0, 1]";
    }
  }
  return "";
}

// A fitted texel: lobes, lookup table, and the texel's average normal
// (surface frame; +z: the lobes live in the surface frame itself).
struct LafortuneModel {
  LafortuneParams params;
  ViewTable lut;
  glm::dvec3 normal{0.0, 0.0, 1.0};
};

// The model's cosine-weighted value T(v) f1(l', v'), with l, v in the
// surface frame and l', v' in the texel's frame; zero unless l.z > 0 and
// v.z > 0. The lookup table is indexed by the measured (surface-frame)
// view.
inline glm::dvec3 LafortuneRho(const LafortuneModel& m, const glm::dvec3& l,
                               const glm::dvec3& v) {
  if (!(l.z > 0.0 && v.z > 0.0)) return glm::dvec3(0.0);
  const TexelFrame frame = MakeTexelFrame(m.normal);
  return LookupView(m.lut, v).color *
         LafortuneF1(m.params, ToTexelFrame(frame, l), ToTexelFrame(frame, v));
}

}  // namespace clothfit
