// The thread BSDF (Sadeghi et al. 2013, eq. 2-4; models/microcylinder_thread.h).
struct CfThread {
  float eta, kd, gamma_s_deg, gamma_v_deg;
  vec3 albedo;
};

float cf_gaussian(float s, float x) {
  return cf_exp_neg(x * x / (2.0 * s * s)) / (s * 2.5066282746310002);
}

float cf_fresnel(float cos_theta, float eta) {
  float c = clamp(cos_theta, 0.0, 1.0);
  float g = sqrt(eta * eta - 1.0 + c * c);
  float a = 0.5 * cf_sqr(g - c) / cf_sqr(g + c);
  float b = 1.0 + cf_sqr(c * (g + c) - 1.0) / cf_sqr(c * (g - c) + 1.0);
  return a * b;
}

struct CfGeometry {
  bool valid;
  float sin_i, sin_o, cos_i, cos_o, theta_h, cos2_d, cos_half_phi_d;
  float cos_phi_i, cos_phi_o, phi_d;
};

const float CF_MIN_PROJECTION2 = 1e-24;

// ProjectOnThread: pi, po the projections on the normal plane of t.
bool cf_project(vec3 t, vec3 n, vec3 wi, vec3 wo, inout CfGeometry g,
                out vec3 pi, out vec3 po) {
  g.sin_i = dot(wi, t);
  g.sin_o = dot(wo, t);
  pi = wi - t * g.sin_i;
  po = wo - t * g.sin_o;
  float pi2 = dot(pi, pi), po2 = dot(po, po);
  if (!(pi2 > CF_MIN_PROJECTION2 && po2 > CF_MIN_PROJECTION2)) return false;
  g.valid = true;
  g.cos_i = sqrt(pi2);
  g.cos_o = sqrt(po2);
  g.cos_phi_i = dot(pi, n) / g.cos_i;
  g.cos_phi_o = dot(po, n) / g.cos_o;
  return true;
}

void cf_azimuth_difference(vec3 pi, vec3 po, inout CfGeometry g) {
  if (g.cos_phi_i > 0.0 && g.cos_phi_o > 0.0) {
    g.phi_d = cf_angle_between(pi, po, g.cos_i * g.cos_o);
  }
}

void cf_half_angles(vec3 pi, vec3 po, inout CfGeometry g) {
  float cos_sum = g.cos_i * g.cos_o - g.sin_i * g.sin_o;
  float sin_sum = g.sin_i * g.cos_o + g.cos_i * g.sin_o;
  float cos_diff = g.cos_i * g.cos_o + g.sin_i * g.sin_o;
  g.theta_h = atan(sin_sum / (1.0 + cos_sum));
  g.cos2_d = max(0.5 * (1.0 + cos_diff), 0.0);
  vec3 half_vector = pi / g.cos_i + po / g.cos_o;
  g.cos_half_phi_d = min(0.5 * cf_safe_sqrt(dot(half_vector, half_vector)), 1.0);
}

CfGeometry cf_no_geometry() {
  return CfGeometry(false, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
}

// (surface, volume): f_rs / cos^2(theta_d) and f_rv / (albedo cos^2(theta_d)).
vec2 cf_thread_lobes(CfGeometry g, CfThread p) {
  float fr = cf_fresnel(sqrt(g.cos2_d) * g.cos_half_phi_d, p.eta);
  float inv_cos2 = 1.0 / g.cos2_d;
  float surface = fr * g.cos_half_phi_d * inv_cos2 *
                  cf_gaussian(cf_radians(p.gamma_s_deg), g.theta_h);
  float volume = cf_sqr(1.0 - fr) * inv_cos2 / (g.cos_i + g.cos_o) *
                 ((1.0 - p.kd) * cf_gaussian(cf_radians(p.gamma_v_deg), g.theta_h) +
                  p.kd);
  return vec2(surface, volume);
}

// f of a thread in the thread frame (tangent +x, normal +z), 1/sr.
vec3 cf_thread_bsdf(CfThread p, vec3 wi, vec3 wo) {
  CfGeometry g = cf_no_geometry();
  vec3 pi, po;
  if (!cf_project(vec3(1.0, 0.0, 0.0), vec3(0.0, 0.0, 1.0), wi, wo, g, pi, po)) {
    return vec3(0.0);
  }
  cf_half_angles(pi, po, g);
  cf_azimuth_difference(pi, po, g);
  vec2 lobes = cf_thread_lobes(g, p);
  return vec3(lobes.x) + p.albedo * lobes.y;
}
