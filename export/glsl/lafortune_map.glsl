// A Lafortune parameter mip map (models/lafortune.h; api/material.h's
// texture maps) with its parameters in the mip-mapped texture array
// cf_params that the renderer binds (RGBA32F, CF_LAYERS layers, CF_LEVELS
// levels of CF_LEVEL_WIDTH[l] x CF_LEVEL_HEIGHT[l] texels, the .params.bin
// file of the export): per texel, layer 0 rho_d (rgb), layer 1 the normal (xyz),
// layers 2 + 4 k .. 5 + 4 k lobe k's Cx, Cy, Cz, N (rgb), then one layer
// per stored view (CF_VIEW[v], shared by the texels) with the texel's
// lookup-table colour. Texture coordinates (s, t) in [0, 1]^2, t's row 0
// first as in the mip map; lod 0 the finest level; CF_FILTER 0 nearest,
// 1 bilinear, 2 trilinear (TexelFilter), blending the texels' values.
uniform highp sampler2DArray cf_params;

vec3 cf_param(ivec2 p, int level, int layer) {
  return texelFetch(cf_params, ivec3(p, layer), level).xyz;
}

vec3 cf_map_lookup(ivec2 p, int level, vec3 v) {
  vec3 color = vec3(0.0);
  float total = 0.0;
  for (int k = 0; k < CF_VIEWS; ++k) {
    vec3 u = CF_VIEW[k];
    float d = cf_angle_between(u, v, length(u) * length(v));
    vec3 c = cf_param(p, level, 2 + 4 * CF_LOBES + k);
    if (d < 1e-12) return c;
    float w = 1.0 / (d * d * d);
    color += w * c;
    total += w;
  }
  return color / total;
}

// rho of texel p of `level` (models/lafortune.h LafortuneRhoInFrame).
vec3 cf_texel_rho(ivec2 p, int level, vec3 l, vec3 v) {
  if (!(l.z > 0.0 && v.z > 0.0)) return vec3(0.0);
  // The texel's frame (MakeTexelFrame).
  vec3 n = cf_param(p, level, 1);
  float len = length(n);
  vec3 ft = vec3(1.0, 0.0, 0.0), fb = vec3(0.0, 1.0, 0.0), fn = vec3(0.0, 0.0, 1.0);
  if (len > 0.0) {
    fn = n / len;
    vec3 b = cross(fn, vec3(1.0, 0.0, 0.0));
    float b_len = length(b);
    fb = b_len > 1e-12 ? b / b_len : vec3(0.0, 1.0, 0.0);
    ft = cross(fb, fn);
  }
  vec3 lt = vec3(dot(l, ft), dot(l, fb), dot(l, fn));
  vec3 vt = vec3(dot(v, ft), dot(v, fb), dot(v, fn));
  vec3 q = lt * vt;
  vec3 sum = cf_param(p, level, 0);
  for (int k = 0; k < CF_LOBES; ++k) {
    vec3 cx = cf_param(p, level, 2 + 4 * k), cy = cf_param(p, level, 3 + 4 * k);
    vec3 cz = cf_param(p, level, 4 + 4 * k), ne = cf_param(p, level, 5 + 4 * k);
    for (int c = 0; c < 3; ++c) {
      float a = cx[c] * q.x + cy[c] * q.y + cz[c] * q.z;
      sum[c] += a > 0.0 ? pow(a, ne[c]) : 0.0;
    }
  }
  vec3 f1 = sum * max(lt.z, 0.0);
  return CF_VIEWS > 0 ? cf_map_lookup(p, level, v) * f1 : f1;
}

// The value of one level at (s, t): nearest, or bilinear (texel centres at
// (x + 0.5) / width, clamped at the edges).
vec3 cf_level_rho(vec2 st, int level, vec3 l, vec3 v) {
  ivec2 size = ivec2(CF_LEVEL_WIDTH[level], CF_LEVEL_HEIGHT[level]);
  vec2 c = clamp(st, 0.0, 1.0);
  if (CF_FILTER == 0) {
    ivec2 p = min(ivec2(c * vec2(size)), size - 1);
    return cf_texel_rho(p, level, l, v);
  }
  vec2 x = c * vec2(size) - 0.5;
  vec2 x0 = floor(x), w = x - x0;
  ivec2 p0 = clamp(ivec2(x0), ivec2(0), size - 1);
  ivec2 p1 = clamp(ivec2(x0) + 1, ivec2(0), size - 1);
  vec3 sum = vec3(0.0);
  if ((1.0 - w.x) * (1.0 - w.y) > 0.0) sum += (1.0 - w.x) * (1.0 - w.y) * cf_texel_rho(p0, level, l, v);
  if (w.x * (1.0 - w.y) > 0.0) sum += w.x * (1.0 - w.y) * cf_texel_rho(ivec2(p1.x, p0.y), level, l, v);
  if ((1.0 - w.x) * w.y > 0.0) sum += (1.0 - w.x) * w.y * cf_texel_rho(ivec2(p0.x, p1.y), level, l, v);
  if (w.x * w.y > 0.0) sum += w.x * w.y * cf_texel_rho(p1, level, l, v);
  return sum;
}

// rho at (s, t) and lod with the export's filter (api/material.h Rho).
vec3 cf_map_rho(vec2 st, float lod, vec3 l, vec3 v) {
  float last = float(CF_LEVELS - 1);
  float d = clamp(lod, 0.0, last);
  if (CF_FILTER != 2) return cf_level_rho(st, int(floor(d + 0.5)), l, v);
  float l0 = floor(d), w1 = d - l0;
  vec3 sum = (1.0 - w1) * cf_level_rho(st, int(l0), l, v);
  if (w1 > 0.0) sum += w1 * cf_level_rho(st, int(l0) + 1, l, v);
  return sum;
}
