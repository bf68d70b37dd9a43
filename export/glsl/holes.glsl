// A semi-transparent layer with thickness (David-Babin 2022, Algorithm 3.1
// and the extension; models/holes.h, models/holes_distance.h, models/
// holes_tile.h): the transmittance of the mask's tile for a view, with the
// export's constants CF_THICKNESS, CF_WALL_COLOR, the tile's CF_TILE
// texels with their base-texel counts CF_TEXELS[i], counts CF_COUNTS[9 i +
// k] (walls top, left, bottom, right; triangles top-right, top-left,
// bottom-left, bottom-right; opaques), cumulative run counts
// CF_RUNS[64 i + 8 d + j] (directions E, N, W, S, NE, NW, SW, SE) when
// CF_EXTENSION, and the tile's area CF_AREA.

// r = -h wo.xy / |wo.z|: the view ray's sideways travel through the layer.
vec2 cf_view_offset(vec3 wo) {
  float z = max(abs(wo.z), 1e-9);
  return CF_THICKNESS * vec2(-wo.x / z, -wo.y / z);
}

// Algorithm 3.1's occluded count O for the offset r clamped to [-1, 1].
float cf_occluded31(int t, vec2 r) {
  float rx = clamp(r.x, -1.0, 1.0), ry = clamp(r.y, -1.0, 1.0);
  int c = 9 * t;
  bool right = rx > 0.0, left = rx < 0.0, top = ry > 0.0, bottom = ry < 0.0;
  float h = right ? CF_COUNTS[c + 3] : (left ? CF_COUNTS[c + 1] : 0.0);
  float v = top ? CF_COUNTS[c + 0] : (bottom ? CF_COUNTS[c + 2] : 0.0);
  float d = 0.0;
  if (right && top) d = CF_COUNTS[c + 4];
  if (right && bottom) d = CF_COUNTS[c + 7];
  if (left && top) d = CF_COUNTS[c + 5];
  if (left && bottom) d = CF_COUNTS[c + 6];
  float ax = right ? rx : -rx, ay = top ? ry : -ry;
  float half_area = 0.5 * ax * ay;
  return h * (ax - half_area) + v * (ay - half_area) + d * half_area;
}

// sum_j (C[j] - C[j-1]) clamp(u - j, 0, 1) over the run counts at `base`.
float cf_run_occlusion(int base, float u) {
  float sum = 0.0, previous = 0.0;
  for (int j = 0; j < 8; ++j) {
    float count = CF_RUNS[base + j] - previous;
    previous = CF_RUNS[base + j];
    if (!(u > float(j))) break;
    if (count != 0.0) sum += count * min(u - float(j), 1.0);
  }
  return sum;
}

// One Sutherland-Hodgman edge: keeps sign (p[axis] - bound) >= 0.
int cf_clip(in vec2 p_in[16], int n, int axis, float bound, float sign,
            out vec2 p_out[16]) {
  int m = 0;
  for (int i = 0; i < 16; ++i) p_out[i] = vec2(0.0);
  for (int i = 0; i < n; ++i) {
    vec2 p = p_in[i], q = p_in[(i + 1) % n];
    float dp = sign * (p[axis] - bound), dq = sign * (q[axis] - bound);
    bool p_inside = dp >= 0.0, q_inside = dq >= 0.0;
    if (p_inside) p_out[m++] = p;
    if (p_inside != q_inside) {
      float s = dp / (dp - dq);
      p_out[m++] = p + (q - p) * s;
    }
  }
  return m;
}

// The area of starts in the unit square whose segment p -> p + (u, v) meets
// the square [1 + m, 2 + m]^2 (models/holes_distance.h DiagonalHitArea).
float cf_diagonal_hit_area(int m, float u, float v) {
  if (!(u > float(m) && v > float(m))) return 0.0;
  float a = 1.0 + float(m);
  vec2 pa[16], pb[16];
  for (int i = 0; i < 16; ++i) pa[i] = vec2(0.0);
  pa[0] = vec2(a - u, a - v);
  pa[1] = vec2(a + 1.0 - u, a - v);
  pa[2] = vec2(a + 1.0, a);
  pa[3] = vec2(a + 1.0, a + 1.0);
  pa[4] = vec2(a, a + 1.0);
  pa[5] = vec2(a - u, a + 1.0 - v);
  int n = 6;
  n = cf_clip(pa, n, 0, 1.0, -1.0, pb);
  n = cf_clip(pb, n, 1, 1.0, -1.0, pa);
  n = cf_clip(pa, n, 0, 0.0, 1.0, pb);
  n = cf_clip(pb, n, 1, 0.0, 1.0, pa);
  float twice = 0.0;
  for (int i = 0; i < n; ++i) {
    vec2 p = pa[i], q = pa[(i + 1) % n];
    twice += p.x * q.y - q.x * p.y;
  }
  return 0.5 * twice;
}

// M(r) of the free-rectangle model for texel t.
float cf_run_model_occluded(int t, vec2 r) {
  float transparent = CF_TEXELS[t] - CF_COUNTS[9 * t + 8];
  if (!(transparent > 0.0)) return 0.0;
  bool east = r.x >= 0.0, north = r.y >= 0.0;
  float u = east ? r.x : -r.x, v = north ? r.y : -r.y;
  int dir_x = east ? 0 : 2, dir_y = north ? 1 : 3;
  int diagonal = east ? (north ? 4 : 7) : (north ? 5 : 6);
  int base = 64 * t;
  float s_x = cf_run_occlusion(base + 8 * dir_x, u);
  float s_y = cf_run_occlusion(base + 8 * dir_y, v);
  float s_d = 0.0, previous = 0.0;
  for (int m = 0; m < 8; ++m) {
    float count = CF_RUNS[base + 8 * diagonal + m] - previous;
    previous = CF_RUNS[base + 8 * diagonal + m];
    if (count != 0.0) s_d += count * cf_diagonal_hit_area(m, u, v);
  }
  float inv = 1.0 / transparent;
  float free_fraction = clamp(1.0 - s_x * inv, 0.0, 1.0) *
                        clamp(1.0 - s_y * inv, 0.0, 1.0) *
                        clamp(1.0 - s_d * inv, 0.0, 1.0);
  return transparent * (1.0 - free_fraction);
}

// The tile's transmittance for the view wo: rho_transparent + wall_color
// rho_occluded, averaged over the tile's texels by their areas.
vec3 cf_holes_transmittance(vec3 wo) {
  vec2 r = cf_view_offset(wo);
  vec2 clamped = clamp(r, vec2(-1.0), vec2(1.0));
  float occluded = 0.0, transparent = 0.0;
  for (int t = 0; t < CF_TILE; ++t) {
    float texels = CF_TEXELS[t], opaque = CF_COUNTS[9 * t + 8];
    float o = cf_occluded31(t, r);
    if (CF_EXTENSION) {
      o = min(o + cf_run_model_occluded(t, r) - cf_run_model_occluded(t, clamped),
              max(texels - opaque, 0.0));
    }
    // sum_t T_t ratios_t = (occluded count, T_t - opaque - occluded count).
    occluded += o;
    transparent += texels - opaque - o;
  }
  return vec3(transparent / CF_AREA) + CF_WALL_COLOR * (occluded / CF_AREA);
}
