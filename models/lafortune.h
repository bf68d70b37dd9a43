// Lafortune lobes with a per-view lookup table (Daubert et al. 2001, eq. 1-2;
// docs/models.md), templated on the scalar type.
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

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include "models/math.h"
#include "models/params.h"

namespace clothfit {

// The parameter table (models/params.h); every entry per channel (r, g,
// b). A lobe's peak over the hemisphere is |C|_inf^N: the base
// a = C . (l * v) is at most max_i |C_i| for unit l and v (reached at
// l = v along the axis of the largest |C_i|, grazing for Cx and Cy). The
// fits keep that peak at most (N + 2) / (2 pi), the peak of a cosine lobe
// whose albedo at normal incidence is 1 (the energy normalisation of the
// modified Phong lobe, Lafortune and Willems 1994): |C_i| <=
// LafortuneLobeReach(N) = ((N + 2) / (2 pi))^(1/N), at most 1.0693 (at
// N = 12.9), a physical bound. N below 0.5 makes a lobe a near-constant,
// above 200 narrower than any measurement resolves: search limits.
// The largest LafortuneLobeReach over N (1.06923 at N = 12.94), the
// outer fit bound of |C|.
inline constexpr double kLafortuneMaxReach = 1.0693;
// Largest |Cx|, |Cy|, |Cz| a file may hold: their products with the
// directions add up without overflow.
inline constexpr double kLafortuneMaxWeight = 1e100;

// The fits' bound on |Cx|, |Cy|, |Cz| of a lobe with exponent n: the lobe's
// peak |C|_inf^N is then at most (N + 2) / (2 pi) (the table's comment),
// and at most peak_cap when that is lower.
template <typename T>
T LafortuneLobeReach(const T& n, double peak_cap = kInfinity) {
  using std::exp;
  using std::log;
  T peak = (n + T(2.0)) / T(2.0 * kPi);
  if (peak > T(peak_cap)) peak = T(peak_cap);
  return exp(log(peak) / n);
}

inline constexpr ParamInfo kLafortuneDiffuse = {
    "diffuse",
    "1/sr",
    "diffuse term rho_d of the bracket (a BRDF value; its albedo is "
    "pi rho_d, at most 1 in a fit; at most 1e3 in a file)",
    {0.0, 1e3},
    0.0,
    1.0 / kPi,
    true,
    {0.25, 0.25, 0.25},
    "Daubert et al. 2001, eq. 2 (rho)",
    3};
inline constexpr ParamInfo kLafortuneCx = {
    "Cx",
    "unitless",
    "weight of l_x v_x in a lobe (any sign, |C| <= 1e100)",
    {-kLafortuneMaxWeight, kLafortuneMaxWeight},
    -kLafortuneMaxReach,
    kLafortuneMaxReach,
    true,
    {-1.0, -1.0, -1.0},
    "Daubert et al. 2001, eq. 2 (C_x); Lafortune et al. 1997",
    3};
inline constexpr ParamInfo kLafortuneCy = {
    "Cy",
    "unitless",
    "weight of l_y v_y in a lobe (any sign, |C| <= 1e100)",
    {-kLafortuneMaxWeight, kLafortuneMaxWeight},
    -kLafortuneMaxReach,
    kLafortuneMaxReach,
    true,
    {-1.0, -1.0, -1.0},
    "Daubert et al. 2001, eq. 2 (C_y); Lafortune et al. 1997",
    3};
inline constexpr ParamInfo kLafortuneCz = {
    "Cz",
    "unitless",
    "weight of l_z v_z in a lobe (any sign, |C| <= 1e100)",
    {-kLafortuneMaxWeight, kLafortuneMaxWeight},
    -kLafortuneMaxReach,
    kLafortuneMaxReach,
    true,
    {1.0, 1.0, 1.0},
    "Daubert et al. 2001, eq. 2 (C_z); Lafortune et al. 1997",
    3};
inline constexpr ParamInfo kLafortuneN = {"N",
                                          "unitless",
                                          "lobe exponent (larger = narrower)",
                                          {0.0, 1e4, true, false},
                                          0.5,
                                          200.0,
                                          false,
                                          {10.0, 10.0, 10.0},
                                          "Daubert et al. 2001, eq. 2 (N)",
                                          3};
// The lobe's largest value, max(|Cx|, |Cy|, |Cz|)^N over the hemisphere,
// may be at most 1e100 (N log10 max|C| <= 100): a file's lobe with Cx =
// -1e200 evaluated to infinity.
inline constexpr double kLafortuneMaxLog10Peak = 100.0;

// Most lobes a parameter set may have (the fits use 0 to 3).
inline constexpr int kMaxLafortuneLobes = 16;

// One lobe (the entries above but the diffuse one).
template <typename T>
struct LafortuneLobeT {
  Vec3<T> cx = kLafortuneCx.DefaultRgb<T>();
  Vec3<T> cy = kLafortuneCy.DefaultRgb<T>();
  Vec3<T> cz = kLafortuneCz.DefaultRgb<T>();
  Vec3<T> n = kLafortuneN.DefaultRgb<T>();
};

// A lobe's entries and fields in table order (the order of the channel
// layout below), for the visitor and for code that indexes them.
inline constexpr const ParamInfo* kLafortuneLobeEntries[4] = {
    &kLafortuneCx, &kLafortuneCy, &kLafortuneCz, &kLafortuneN};
template <typename T>
inline constexpr Vec3<T> LafortuneLobeT<T>::*kLafortuneLobeFields[4] = {
    &LafortuneLobeT<T>::cx, &LafortuneLobeT<T>::cy, &LafortuneLobeT<T>::cz,
    &LafortuneLobeT<T>::n};

template <typename T, typename F>
void VisitParams(LafortuneLobeT<T>& lobe, F&& f) {
  for (int q = 0; q < 4; ++q) {
    f(*kLafortuneLobeEntries[q], lobe.*kLafortuneLobeFields<T>[q]);
  }
}

template <typename T>
struct LafortuneParamsT {
  Vec3<T> diffuse = kLafortuneDiffuse.DefaultRgb<T>();
  std::vector<LafortuneLobeT<T>> lobes;
};
using LafortuneLobe = LafortuneLobeT<double>;
using LafortuneParams = LafortuneParamsT<double>;

// Entries per channel of the channel layout: rho_d, then Cx, Cy, Cz, N
// per lobe.
inline int LafortuneChannelSize(int lobes) { return 1 + 4 * lobes; }

// The parameters of one channel c as a flat array (the layout the fit and
// LobeSum use): [rho_d, Cx_0, Cy_0, Cz_0, N_0, Cx_1, ...].
template <typename T>
void LafortuneChannelToArray(const LafortuneParamsT<T>& p, int c, T* x) {
  *x++ = p.diffuse[c];
  for (const LafortuneLobeT<T>& lobe : p.lobes) {
    VisitParamsConst(
        lobe, [&](const ParamInfo&, const Vec3<T>& field) { *x++ = field[c]; });
  }
}

// Inverse of LafortuneChannelToArray for channel c of *p (which must have
// the lobes).
template <typename T>
void LafortuneChannelFromArray(const T* x, int c, LafortuneParamsT<T>* p) {
  p->diffuse[c] = *x++;
  for (LafortuneLobeT<T>& lobe : p->lobes) {
    VisitParams(lobe,
                [&](const ParamInfo&, Vec3<T>& field) { field[c] = *x++; });
  }
}

// The table's ranges, each message naming the entry by its path
// ("lobes[1].N: component 0 must be in (0, 10000], got -1").
inline std::string ValidateLafortuneParams(const LafortuneParams& p) {
  for (int c = 0; c < 3; ++c) {
    const std::string e = CheckParam(kLafortuneDiffuse, p.diffuse[c], c);
    if (!e.empty()) return e;
  }
  if (p.lobes.size() > static_cast<size_t>(kMaxLafortuneLobes)) {
    return "lobes: at most " + std::to_string(kMaxLafortuneLobes) +
           " lobes, got " + std::to_string(p.lobes.size());
  }
  for (size_t k = 0; k < p.lobes.size(); ++k) {
    const LafortuneLobe& lobe = p.lobes[k];
    const std::string e = ValidateParams(lobe);
    if (!e.empty()) return "lobes[" + std::to_string(k) + "]." + e;
    for (int c = 0; c < 3; ++c) {
      const double reach = std::max(
          {std::abs(lobe.cx[c]), std::abs(lobe.cy[c]), std::abs(lobe.cz[c])});
      if (reach > 1.0 &&
          lobe.n[c] * std::log10(reach) > kLafortuneMaxLog10Peak) {
        std::ostringstream msg;
        msg.precision(4);
        msg << "lobes[" << k << "]: channel " << c
            << ": max(|Cx|, |Cy|, |Cz|)^N = 10^"
            << lobe.n[c] * std::log10(reach)
            << " overflows; it must be at most 1e100";
        return msg.str();
      }
    }
  }
  return "";
}

// [a]^N: a^N for a > 0, else 0 (value and derivatives).
// For double and float one pow call; for Jets exp(N log a), whose
// derivatives are
// those of a^N (d/da = N a^(N-1), d/dN = a^N log a).
template <typename T>
T LobePower(const T& a, const T& n) {
  using std::exp;
  using std::log;
  if (!(a > T(0.0))) return T(0.0);
  if constexpr (std::is_floating_point_v<T>) {
    return std::pow(a, n);
  } else {
    return exp(n * log(a));
  }
}

// Whether a lobe is grey: every channel's Cx, Cy, Cz and N the same (a
// one-channel table's fit, or a grey texel).
template <typename T>
bool LafortuneLobeGrey(const LafortuneLobeT<T>& lobe) {
  for (int c = 1; c < 3; ++c) {
    if (!(lobe.cx[c] == lobe.cx[0] && lobe.cy[c] == lobe.cy[0] &&
          lobe.cz[c] == lobe.cz[0] && lobe.n[c] == lobe.n[0])) {
      return false;
    }
  }
  return true;
}

// The bracket of eq. 2, rho_d + sum_k [Cx xx + Cy yy + Cz zz]^N, for C
// channels at once (lobes outer, channels inner), with the products
// xx = l_x v_x, yy = l_y v_y, zz = l_z v_z. `diffuse(c)` returns rho_d of
// channel c, `lobe(k, q, c)` entry q (Cx, Cy, Cz, N) of lobe k, and
// `grey(k)` whether lobe k is grey (LafortuneLobeGrey; asked only of
// floating-point parameters). The products' scalar type G may differ from
// the parameters' T: a fit multiplies fixed double products with Jet
// parameters, a third of the cost of Jet times Jet.
template <int C, typename T, typename G, typename Diffuse, typename Lobe,
          typename Grey>
std::array<T, C> LobeSums(const Diffuse& diffuse, const Lobe& lobe,
                          const Grey& grey, int lobes, const G& xx, const G& yy,
                          const G& zz) {
  std::array<T, C> sum;
  for (int c = 0; c < C; ++c) sum[c] = diffuse(c);
  for (int k = 0; k < lobes; ++k) {
    if constexpr (std::is_floating_point_v<T> && C > 1) {
      // A grey lobe has one power for all channels, the same value bit
      // for bit.
      if (grey(k)) {
        const T power = LobePower(
            lobe(k, 0, 0) * xx + lobe(k, 1, 0) * yy + lobe(k, 2, 0) * zz,
            lobe(k, 3, 0));
        for (int c = 0; c < C; ++c) sum[c] += power;
        continue;
      }
    }
    for (int c = 0; c < C; ++c) {
      sum[c] += LobePower(
          lobe(k, 0, c) * xx + lobe(k, 1, c) * yy + lobe(k, 2, c) * zz,
          lobe(k, 3, c));
    }
  }
  return sum;
}

// The bracket of one channel from its channel array x
// (LafortuneChannelToArray: rho_d, then Cx, Cy, Cz, N of each lobe).
template <typename T, typename G>
T LobeSum(const T* x, int lobes, const G& xx, const G& yy, const G& zz) {
  return LobeSums<1, T>(
      [x](int) -> const T& { return x[0]; },
      [x](int k, int q, int) -> const T& { return x[1 + 4 * k + q]; },
      [](int) { return false; }, lobes, xx, yy, zz)[0];
}

// The foreshortening l.z of eq. 2, taken as 0 below the texel's plane.
template <typename G>
G Foreshortening(const Vec3<G>& l) {
  return l.z > G(0.0) ? l.z : G(0.0);
}

// f1 of one channel (eq. 2) from its channel array.
template <typename T, typename G>
T LafortuneF1Channel(const T* x, int lobes, const Vec3<G>& l,
                     const Vec3<G>& v) {
  return LobeSum(x, lobes, l.x * v.x, l.y * v.y, l.z * v.z) * Foreshortening(l);
}

// f1 per channel (eq. 2), reading the lobes where they are.
// grey(k): whether lobe k is grey (LafortuneLobeGrey, or known).
template <typename T, typename G, typename Grey>
Vec3<T> LafortuneF1With(const LafortuneParamsT<T>& p, const Grey& grey,
                        const Vec3<G>& l, const Vec3<G>& v) {
  const std::array<T, 3> sum = LobeSums<3, T>(
      [&p](int c) -> const T& { return p.diffuse[c]; },
      [&p](int k, int q, int c) -> const T& {
        return (p.lobes[k].*kLafortuneLobeFields<T>[q])[c];
      },
      grey, static_cast<int>(p.lobes.size()), l.x* v.x, l.y* v.y, l.z* v.z);
  const T foreshortening(Foreshortening(l));
  return Vec3<T>(sum[0], sum[1], sum[2]) * foreshortening;
}

template <typename T, typename G>
Vec3<T> LafortuneF1(const LafortuneParamsT<T>& p, const Vec3<G>& l,
                    const Vec3<G>& v) {
  return LafortuneF1With(
      p, [&p](int k) { return LafortuneLobeGrey(p.lobes[k]); }, l, v);
}

// A texel's local frame: tangent, bi-normal, normal (unit, right-handed).
template <typename T>
struct TexelFrameT {
  Vec3<T> t = Vec3<T>(T(1.0), T(0.0), T(0.0));
  Vec3<T> b = Vec3<T>(T(0.0), T(1.0), T(0.0));
  Vec3<T> n = Vec3<T>(T(0.0), T(0.0), T(1.0));
};
using TexelFrame = TexelFrameT<double>;

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
template <typename T>
Vec3<T> ToTexelFrame(const TexelFrameT<T>& f, const Vec3<T>& w) {
  return Vec3<T>(glm::dot(w, f.t), glm::dot(w, f.b), glm::dot(w, f.n));
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

// The name of that interpolation in parameter files and mip maps.
inline constexpr char kLutInterpolation[] = "shepard, angular distance power 3";

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
      if (!(std::abs(t.color[k][c]) <= 1e3)) {
        return "lut.color[" + std::to_string(k) +
               "]: must be finite, at most 1e3 in magnitude";
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
// LafortuneRhoInFrame takes the texel's frame made once (MakeTexelFrame of
// the normal) and evaluates in any floating-point type (the table's
// lookup in double); with `shape`, what else a renderer knows of the texel
// beforehand.
struct LafortuneShape {
  bool surface_frame = false;  // the frame is the surface's (normal +z)
  std::array<bool, kMaxLafortuneLobes> grey{};  // LafortuneLobeGrey
};

template <typename T>
LafortuneShape MakeLafortuneShape(const LafortuneParamsT<T>& p,
                                  const TexelFrameT<T>& frame) {
  LafortuneShape shape;
  const TexelFrameT<T> surface;
  shape.surface_frame =
      frame.t == surface.t && frame.b == surface.b && frame.n == surface.n;
  for (size_t k = 0; k < p.lobes.size() && k < shape.grey.size(); ++k) {
    shape.grey[k] = LafortuneLobeGrey(p.lobes[k]);
  }
  return shape;
}

template <typename T>
Vec3<T> LafortuneRhoInFrame(const LafortuneParamsT<T>& p,
                            const TexelFrameT<T>& frame, const ViewTable& lut,
                            const Vec3<T>& l, const Vec3<T>& v,
                            const LafortuneShape* shape = nullptr) {
  if (!(l.z > T(0.0) && v.z > T(0.0))) return Vec3<T>(T(0.0));
  Vec3<T> f1;
  if (shape == nullptr) {
    f1 = LafortuneF1(p, ToTexelFrame(frame, l), ToTexelFrame(frame, v));
  } else {
    // In the surface frame, ToTexelFrame is the identity (w.x + 0 + 0).
    const auto grey = [shape](int k) { return shape->grey[k]; };
    f1 = shape->surface_frame ? LafortuneF1With(p, grey, l, v)
                              : LafortuneF1With(p, grey, ToTexelFrame(frame, l),
                                                ToTexelFrame(frame, v));
  }
  if (lut.views.empty()) return f1;  // T(v) = 1
  return Vec3<T>(LookupView(lut, glm::dvec3(v)).color) * f1;
}

inline glm::dvec3 LafortuneRho(const LafortuneModel& m, const glm::dvec3& l,
                               const glm::dvec3& v) {
  return LafortuneRhoInFrame(m.params, MakeTexelFrame(m.normal), m.lut, l, v);
}

template <>
inline constexpr ModelInfo kModelInfo<LafortuneModel> = {
    "lafortune", Quantity::kCosineWeighted, false};

inline glm::dvec3 NativeValue(const LafortuneModel& m, const glm::dvec3& wi,
                              const glm::dvec3& wo) {
  return LafortuneRho(m, wi, wo);
}

}  // namespace clothfit
