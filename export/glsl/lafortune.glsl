// Lafortune lobes with a per-view lookup table (Daubert et al. 2001, eq. 1-4;
// models/lafortune.h) with the export's constants: rho_d CF_DIFFUSE, lobes
// k < CF_LOBES with CF_CX[k], CF_CY[k], CF_CZ[k], CF_NEXP[k] (rgb), the
// texel frame CF_FT, CF_FB, CF_FN, and CF_VIEWS stored views CF_VIEW[v]
// with colours CF_VCOLOR[v] (Shepard's interpolation, angular distance
// power 3).
float cf_lobe_power(float a, float n) { return a > 0.0 ? pow(a, n) : 0.0; }

vec3 cf_lookup_view(vec3 v) {
  vec3 color = vec3(0.0);
  float total = 0.0;
  for (int k = 0; k < CF_VIEWS; ++k) {
    vec3 u = CF_VIEW[k];
    float d = cf_angle_between(u, v, length(u) * length(v));
    if (d < 1e-12) return CF_VCOLOR[k];
    float w = 1.0 / (d * d * d);
    color += w * CF_VCOLOR[k];
    total += w;
  }
  return color / total;
}

// rho = T(v) f1(l', v') (the model's cosine-weighted value).
vec3 cf_lafortune_rho(vec3 l, vec3 v) {
  if (!(l.z > 0.0 && v.z > 0.0)) return vec3(0.0);
  vec3 lt = vec3(dot(l, CF_FT), dot(l, CF_FB), dot(l, CF_FN));
  vec3 vt = vec3(dot(v, CF_FT), dot(v, CF_FB), dot(v, CF_FN));
  vec3 p = lt * vt;
  vec3 sum = CF_DIFFUSE;
  for (int k = 0; k < CF_LOBES; ++k) {
    for (int c = 0; c < 3; ++c) {
      sum[c] += cf_lobe_power(
          CF_CX[k][c] * p.x + CF_CY[k][c] * p.y + CF_CZ[k][c] * p.z, CF_NEXP[k][c]);
    }
  }
  vec3 f1 = sum * max(lt.z, 0.0);
  return CF_VIEWS > 0 ? cf_lookup_view(v) * f1 : f1;
}
