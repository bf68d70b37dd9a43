// The energy bound of a thread or cloth (models/energy_bound.h,
// EnergyBoundFactor), with the export's constants: CF_BOUNDED (false: the
// paper's model), CF_BOUND_NODES entries of CF_BOUND_LIGHT (c A_L) and
// CF_BOUND_VIEW (A_V) at the nodes c_k = (k / (CF_BOUND_NODES - 1))^2.
float cf_bound_table(bool light, float c) {
  float x = sqrt(clamp(c, 0.0, 1.0)) * float(CF_BOUND_NODES - 1);
  int k = min(CF_BOUND_NODES - 2, int(x));
  float a = light ? CF_BOUND_LIGHT[k] : CF_BOUND_VIEW[k];
  float b = light ? CF_BOUND_LIGHT[k + 1] : CF_BOUND_VIEW[k + 1];
  return a + (x - float(k)) * (b - a);
}

// f' / f at the cosines ci = wi.z, co = wo.z: the horizon fade below
// cos 87 degrees and the division by the larger albedo.
float cf_energy_bound(float ci, float co) {
  if (!CF_BOUNDED || !(ci > 0.0) || !(co > 0.0)) return 1.0;
  const float fade_cos = 0.0523359562;
  float fade = min(1.0, ci / fade_cos) * min(1.0, co / fade_cos);
  float d = max(max(ci, cf_bound_table(true, ci)),
                ci * cf_bound_table(false, co));
  return fade * ci / d;
}
