// The optically thin slab (Frisvad et al.; models/slab.h) with the export's
// constants CF_TAU and CF_ALBEDO (rgb): reflection when wi and wo are on one
// side, diffuse transmission when on opposite sides (f, 1/sr), and the direct
// transmittance exp(-tau / |w.z|).
const float CF_SLAB_MIN_MU = 1e-15;  // mu_i mu_o stays a normal float

// E(y) = (1 - exp(-y)) / y for y >= 0 (models/slab.h MeanAttenuation):
// its Taylor series below 0.25, the closed form above.
float cf_mean_attenuation(float y) {
  if (y >= 0.25) return (1.0 - exp(-y)) / y;
  const float k[14] = float[14](1.0, 1.0 / 2.0, 1.0 / 6.0, 1.0 / 24.0,
      1.0 / 120.0, 1.0 / 720.0, 1.0 / 5040.0, 1.0 / 40320.0, 1.0 / 362880.0,
      1.0 / 3628800.0, 1.0 / 39916800.0, 1.0 / 479001600.0,
      1.0 / 6227020800.0, 1.0 / 87178291200.0);
  float s = k[13];
  for (int i = 12; i >= 0; --i) s = s * -y + k[i];
  return s;
}

float cf_slab_reflection(float tau, float mu_i, float mu_o) {
  float sum = mu_i + mu_o;
  if (!(min(mu_i, mu_o) > CF_SLAB_MIN_MU)) return 1.0 / max(sum, 1e-7);
  float x = tau * sum / (mu_i * mu_o);
  return x * cf_mean_attenuation(x) / sum;
}

float cf_slab_transmission(float tau, float mu_i, float mu_o) {
  float hi = max(mu_i, mu_o), lo = min(mu_i, mu_o);
  if (!(hi > CF_SLAB_MIN_MU)) return 0.0;
  float outer = exp(-tau / hi);
  if (!(lo > CF_SLAB_MIN_MU)) return outer / hi;
  float y = tau * (hi - lo) / (hi * lo);
  if (y < 0.25) return tau / (hi * lo) * outer * cf_mean_attenuation(y);
  return outer * (1.0 - exp(-y)) / (hi - lo);
}

vec3 cf_slab_bsdf(vec3 wi, vec3 wo) {
  float mu_i = abs(wi.z), mu_o = abs(wo.z);
  bool transmits = wi.z * wo.z < 0.0;
  vec3 f;
  for (int c = 0; c < 3; ++c) {
    f[c] = CF_ALBEDO[c] / (4.0 * CF_PI) *
           (transmits ? cf_slab_transmission(CF_TAU[c], mu_i, mu_o)
                      : cf_slab_reflection(CF_TAU[c], mu_i, mu_o));
  }
  return f;
}

vec3 cf_slab_direct_transmittance(vec3 w) {
  float mu = abs(w.z);
  return mu > CF_SLAB_MIN_MU ? exp(-CF_TAU / mu) : vec3(0.0);
}
