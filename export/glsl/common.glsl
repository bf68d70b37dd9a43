// clothfit GLSL (ES 3.00): the models of clothfit's models/*.h, the one
// second copy of their formulas, kept equal by tests/glsl_browser_test.cc
// (values within 1e-4 of the C++ ones). Directions are unit vectors in the
// surface frame (normal +z, warp +x, weft +y; a thread file: the thread
// frame, tangent +x), both pointing away from the surface.
const float CF_PI = 3.14159265358979;

float cf_sqr(float x) { return x * x; }
float cf_safe_sqrt(float x) { return x > 0.0 ? sqrt(x) : 0.0; }
// exp(-x), exactly 0 where float underflows (models/math.h ExpNeg).
float cf_exp_neg(float x) { return x > 103.0 ? 0.0 : exp(-x); }
float cf_radians(float deg) { return deg * (CF_PI / 180.0); }

// The angle between a and b (|a| |b| = norm_product), from half-angle
// arctangents (models/math.h AngleBetween).
float cf_angle_between(vec3 a, vec3 b, float norm_product) {
  vec3 c = cross(a, b);
  float s = cf_safe_sqrt(dot(c, c));
  float k = dot(a, b);
  if (k >= 0.0) return 2.0 * atan(s / (norm_product + k));
  return CF_PI - 2.0 * atan(s / (norm_product - k));
}
