// The cloth patch (Sadeghi et al. 2013, eq. 5-13; models/microcylinder_cloth.h)
// with the export's constants: CF_THREADS threads, CF_THREAD[j] their
// scattering parameters, CF_COVERAGE[j], CF_TOTAL[j] their numbers of
// tangent samples, the distinct sample frames CF_T[k], CF_N[k] of thread j,
// k in [CF_FIRST[j], CF_FIRST[j + 1]), each standing for CF_REPEATS[k]
// samples at the same offset (their terms added once and multiplied),
// CF_DIFFUSE and CF_SCALE.
float cf_masking_blend(float angle_d) {
  const float w = 20.0 * CF_PI / 180.0;
  return cf_exp_neg(angle_d * angle_d / (2.0 * w * w));
}

float cf_masking(float cos_i, float cos_o, float u) {
  if (!(cos_i > 0.0 && cos_o > 0.0)) return 0.0;
  return (1.0 - u) * cos_i * cos_o + u * min(cos_i, cos_o);
}

// rho = f wi.z of the cloth (eq. 13) times its scale.
vec3 cf_cloth_rho(vec3 wi, vec3 wo) {
  if (!(wi.z > 0.0 && wo.z > 0.0)) return vec3(0.0);
  vec3 sum = vec3(0.0);
  float weighted = 0.0, coverage = 0.0;
  for (int j = 0; j < CF_THREADS; ++j) {
    int first = CF_FIRST[j], last = CF_FIRST[j + 1];
    float surface = 0.0, volume = 0.0, w = 0.0;
    if (last > first) {
      // The psi plane, shared by the thread's samples (b = t x n = d x z).
      vec3 b = cross(CF_T[first], CF_N[first]);
      vec3 qi = wi - b * dot(wi, b), qo = wo - b * dot(wo, b);
      float qi2 = dot(qi, qi), qo2 = dot(qo, qo);
      if (qi2 > CF_MIN_PROJECTION2 && qo2 > CF_MIN_PROJECTION2) {
        float qi_len = sqrt(qi2), qo_len = sqrt(qo2);
        float u = cf_masking_blend(cf_angle_between(qi, qo, qi_len * qo_len));
        for (int k = first; k < last; ++k) {
          CfGeometry g = cf_no_geometry();
          vec3 pi, po;
          if (!cf_project(CF_T[k], CF_N[k], wi, wo, g, pi, po)) continue;
          float reweight = cf_masking(dot(qi, CF_N[k]) / qi_len,
                                      dot(qo, CF_N[k]) / qo_len, u) *
                           CF_REPEATS[k];
          w += reweight;
          if (!(reweight > 0.0)) continue;
          cf_azimuth_difference(pi, po, g);
          float weight = 0.0;
          if (g.cos_phi_i > 0.0 && g.cos_phi_o > 0.0) {
            weight = cf_masking(g.cos_phi_i, g.cos_phi_o,
                                cf_masking_blend(g.phi_d)) *
                     reweight * g.cos_i;
          }
          if (weight > 0.0) {
            cf_half_angles(pi, po, g);
            vec2 lobes = cf_thread_lobes(g, CF_THREAD[j]);
            surface += lobes.x * weight;
            volume += lobes.y * weight;
          }
        }
      }
    }
    float inv_count = CF_TOTAL[j] > 0.0 ? 1.0 / CF_TOTAL[j] : 0.0;
    sum += (vec3(surface) + CF_THREAD[j].albedo * volume) * inv_count *
           CF_COVERAGE[j];
    coverage += CF_COVERAGE[j];
    weighted += CF_COVERAGE[j] * w * inv_count;
  }
  vec3 diffuse = CF_DIFFUSE * (wi.z / CF_PI);
  float q = weighted + (1.0 - coverage) * wi.z;
  return (q > 0.0 ? sum / q + diffuse : diffuse) * CF_SCALE;
}
