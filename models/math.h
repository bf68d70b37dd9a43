// Scalar helpers shared by the models. Every function is templated on the
// scalar type T so that it evaluates both double and Ceres Jets; comparisons
// use the value part only, which is what Jets implement.
#pragma once

#include <cmath>
#include <type_traits>

// GLM's vectors hold x/r/s in anonymous unions, which delete copying for
// scalar types with non-trivial copies such as Ceres Jets. Plain x, y, z
// members fix that; the clothfit::models target sets this for every user.
#ifndef GLM_FORCE_XYZW_ONLY
#define GLM_FORCE_XYZW_ONLY
#endif
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

// CLOTHFIT_INLINE_ALL: GCC's and Clang's flatten attribute (everything the
// function calls is inlined into it), for innermost evaluations. Off under
// the sanitizers: with their instrumentation inlined too, GCC compiled a
// fit's residual for over 8 minutes and 5 GB without finishing.
#if defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(memory_sanitizer) || \
    __has_feature(thread_sanitizer)
#define CLOTHFIT_NO_INLINE_ALL
#endif
#endif
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define CLOTHFIT_NO_INLINE_ALL
#endif
#if (defined(__GNUC__) || defined(__clang__)) && \
    !defined(CLOTHFIT_NO_INLINE_ALL)
#define CLOTHFIT_INLINE_ALL __attribute__((flatten))
#else
#define CLOTHFIT_INLINE_ALL
#endif

namespace clothfit {

inline constexpr double kPi = 3.14159265358979323846;

template <typename T>
using Vec2 = glm::vec<2, T>;
template <typename T>
using Vec3 = glm::vec<3, T>;

template <typename T>
inline T Sqr(const T& x) {
  return x * x;
}

template <typename T>
inline T Max(const T& a, const T& b) {
  return a > b ? a : b;
}

template <typename T>
inline T Min(const T& a, const T& b) {
  return a < b ? a : b;
}

template <typename T>
inline T Clamp(const T& x, const T& lo, const T& hi) {
  return Min(Max(x, lo), hi);
}

// sqrt(max(x, 0)), with value and derivative 0 at x <= 0 (the derivative of
// sqrt at 0 is infinite, which would poison a Jacobian with Inf).
template <typename T>
inline T SafeSqrt(const T& x) {
  using std::sqrt;
  if (!(x > T(0))) return T(0) * x;
  return sqrt(x);
}

// The one conversion between degrees (files, messages) and radians (code).
template <typename T>
constexpr T Radians(const T& degrees) {
  return degrees * T(kPi / 180.0);
}

template <typename T>
constexpr T Degrees(const T& radians) {
  return radians * T(180.0 / kPi);
}

// exp(-x) for x >= 0. Where the result is below half the smallest
// subnormal of a floating-point T (x > 105 for float, 746 for double) it is
// exactly 0, returned without the library's slow underflow path (a
// narrow Gaussian lobe's tail in float). Jets take exp as it is.
template <typename T>
inline T ExpNeg(const T& x) {
  using std::exp;
  if constexpr (std::is_floating_point_v<T>) {
    constexpr T kZeroBeyond = sizeof(T) == sizeof(float) ? T(105) : T(746);
    if (x > kZeroBeyond) return T(0);
  }
  return exp(-x);
}

// Converts a vector to the scalar type T.
template <typename T, typename G>
inline Vec3<T> Cast(const Vec3<G>& v) {
  return Vec3<T>(T(v.x), T(v.y), T(v.z));
}

// Unsigned angle in [0, pi] between vectors a and b whose lengths multiply to
// `norm_product`, by the half-angle form angle = 2 atan(|a x b| / (|a||b| +
// a.b)), switching to pi - 2 atan(|a x b| / (|a||b| - a.b)) for obtuse angles
// so that the denominator never falls below |a||b|. Accurate near 0 and pi
// (unlike acos of a dot product) and about twice as fast as atan2.
// AngleFromParts takes |a x b| and a.b.
template <typename T>
inline T AngleFromParts(const T& sin_part, const T& cos_part,
                        const T& norm_product) {
  using std::atan;
  if (cos_part >= T(0.0)) {
    return T(2.0) * atan(sin_part / (norm_product + cos_part));
  }
  return T(kPi) - T(2.0) * atan(sin_part / (norm_product - cos_part));
}

template <typename T>
inline T AngleBetween(const Vec3<T>& a, const Vec3<T>& b,
                      const T& norm_product) {
  const Vec3<T> c = glm::cross(a, b);
  return AngleFromParts(SafeSqrt(glm::dot(c, c)), glm::dot(a, b), norm_product);
}

// The same for vectors in a plane (|a x b| = |a.x b.y - a.y b.x|).
template <typename T>
inline T AngleBetween(const Vec2<T>& a, const Vec2<T>& b,
                      const T& norm_product) {
  using std::abs;
  return AngleFromParts(T(abs(a.x * b.y - a.y * b.x)), glm::dot(a, b),
                        norm_product);
}

}  // namespace clothfit
