#version 450
// caustic_volume's per-fragment test (methods/caustic_volume/containment.cpp, in float): the receiver
// point of the pixel against the volume, the cubic in t whose roots are the cross-sections through it,
// the barycentric test on each, and the light of each sheet it lies on (interpolated or constant
// intensity, the medium's absorption, the cosine to the interpolated direction). Added into the image with
// the other volumes' (blend one + one, in the volumes' order as the CPU adds them); a second target
// counts the tests and the tests that found light.
layout(std430, binding = 0) readonly buffer Footprints { vec4 footprints[]; };
layout(std430, binding = 1) readonly buffer Volumes { vec4 volumes[]; };
layout(std430, binding = 2) readonly buffer Positions { vec4 positions[]; };
layout(std430, binding = 3) readonly buffer Normals { vec4 normals[]; };
layout(std430, binding = 4) readonly buffer Objects { float objects[]; };

layout(push_constant) uniform Parameters {
  uint width;
  uint height;
  uint intensity;  // 0 interpolated, 1 constant
} parameters;

layout(location = 0) flat in uint volume;
layout(location = 0) out vec4 irradiance;
layout(location = 1) out vec4 counts;

const uint kVolumeVec4 = 19u;

vec4 at(uint field) { return volumes[kVolumeVec4 * volume + field]; }

float g_of(vec4 a, float u) { return ((a.w * u + a.z) * u + a.y) * u + a.x; }

// A root of g in [lo, hi] where g changes sign: regula falsi, Illinois (containment.cpp's bracketed_root).
float bracketed_root(vec4 a, float lo, float hi, float g_lo, float g_hi, float size) {
  int side = 0;
  for (int iteration = 0; iteration < 64; ++iteration) {
    float mid = (lo * g_hi - hi * g_lo) / (g_hi - g_lo);
    if (!(mid > lo && mid < hi)) mid = 0.5 * (lo + hi);
    const float g_mid = g_of(a, mid);
    if (abs(g_mid) <= 1e-7 * size || hi - lo <= 1e-7) return mid;
    if ((g_mid < 0.0) == (g_lo < 0.0)) {
      lo = mid;
      g_lo = g_mid;
      if (side == -1) g_hi *= 0.5;
      side = -1;
    } else {
      hi = mid;
      g_hi = g_mid;
      if (side == 1) g_lo *= 0.5;
      side = 1;
    }
  }
  return abs(g_lo) < abs(g_hi) ? lo : hi;
}

// Every real root of c0 + c1 t + c2 t^2 + c3 t^3 in [0, t_max], ascending (cubic_roots).
int cubic_roots(float c0, float c1, float c2, float c3, float t_max, out float roots[3]) {
  const vec4 a = vec4(c0, c1 * t_max, c2 * t_max * t_max, c3 * t_max * t_max * t_max);
  const float size = abs(a.x) + abs(a.y) + abs(a.z) + abs(a.w);
  float breaks[4] = float[4](0.0, 0.0, 0.0, 1.0);
  int count = 1;
  const float qa = 3.0 * a.w, qb = 2.0 * a.z, qc = a.y;
  const float scale = abs(qa) + abs(qb) + abs(qc);
  if (scale > 0.0) {
    float critical[2] = float[2](0.0, 0.0);
    int found = 0;
    if (abs(qa) <= 1e-7 * scale) {
      if (qb != 0.0) critical[found++] = -qc / qb;
    } else {
      const float discriminant = qb * qb - 4.0 * qa * qc;
      if (discriminant >= 0.0) {
        const float q = -0.5 * (qb + (qb < 0.0 ? -1.0 : 1.0) * sqrt(discriminant));
        critical[found++] = q / qa;
        if (q != 0.0) critical[found++] = qc / q;
      }
    }
    if (found == 2 && critical[1] < critical[0]) critical = float[2](critical[1], critical[0]);
    for (int i = 0; i < found; ++i)
      if (critical[i] > 0.0 && critical[i] < 1.0) breaks[count++] = critical[i];
  }
  breaks[count++] = 1.0;
  int n = 0;
  roots = float[3](0.0, 0.0, 0.0);
  float g_previous = g_of(a, breaks[0]);
  if (g_previous == 0.0) roots[n++] = 0.0;
  for (int i = 1; i < count && n < 3; ++i) {
    const float g_here = g_of(a, breaks[i]);
    if (g_here == 0.0) {
      if (breaks[i] > (n > 0 ? roots[n - 1] / t_max : -1.0)) roots[n++] = breaks[i] * t_max;
    } else if (g_previous != 0.0 && (g_here < 0.0) != (g_previous < 0.0)) {
      roots[n++] = bracketed_root(a, breaks[i - 1], breaks[i], g_previous, g_here, size) * t_max;
    }
    g_previous = g_here;
  }
  return n;
}

// The light of the sheet at t through the point, with barycentric weights w (beam_irradiance).
vec3 beam_irradiance(float t, vec3 w) {
  if (parameters.intensity == 1u) {
    const vec3 entering = (at(6u).xyz + at(7u).xyz + at(8u).xyz) / 3.0;
    const vec3 section = at(16u).xyz + t * at(17u).xyz + t * t * at(18u).xyz;
    const float area_in = at(1u).w;
    const float area_out = 0.5 * abs(dot(section, at(12u).xyz));
    return entering * (area_in / max(area_out, 1e-4 * area_in));
  }
  vec3 flux = vec3(0.0);
  float area_out = 0.0, area_in = 0.0;
  for (uint i = 0u; i < 3u; ++i) {
    const vec4 arriving = at(6u + i);
    const vec3 q = at(9u + i).xyz;
    flux += arriving.xyz * (w[i] * arriving.w);
    area_in += w[i] * arriving.w;
    area_out += w[i] * abs(q.x + t * (q.y + t * q.z));
  }
  return flux / max(area_out, 1e-4 * area_in);
}

void main() {
  const uint pixel = uint(gl_FragCoord.y) * parameters.width + uint(gl_FragCoord.x);
  const vec4 position = positions[pixel];
  if (position.w == 0.0) discard;  // not a receiver: not tested
  const vec3 x = position.xyz, n = normals[pixel].xyz;
  irradiance = vec4(0.0);
  counts = vec4(1.0, 0.0, 0.0, 0.0);
  const vec3 lower = at(14u).xyz, upper = at(15u).xyz;
  if (any(lessThan(x, lower)) || any(greaterThan(x, upper))) return;
  const vec3 p0 = at(0u).xyz, p1 = at(1u).xyz, p2 = at(2u).xyz;
  const vec3 d0 = at(3u).xyz, d1 = at(4u).xyz, d2 = at(5u).xyz;
  const float t_max = at(0u).w;
  const float t_min = objects[pixel] == at(3u).w ? at(2u).w : 0.0;
  // det[E1(t), E2(t), x - T0(t)] = (k0 + k1 t + k2 t^2) . (c - t D0), c = x - P0: a cubic in t.
  const vec3 c = x - p0;
  const vec4 k0 = at(16u), k1 = at(17u), k2 = at(18u);
  float roots[3];
  const int count = cubic_roots(dot(k0.xyz, c), dot(k1.xyz, c) - k0.w, dot(k2.xyz, c) - k1.w, -k2.w, t_max, roots);
  const vec3 a1 = p1 - p0, a2 = p2 - p0, b1 = d1 - d0, b2 = d2 - d0;
  const vec3 absorption = at(13u).xyz;
  vec3 sum = vec3(0.0);
  for (int r = 0; r < count; ++r) {
    const float t = roots[r];
    if (t < t_min) continue;
    const vec3 e1 = a1 + t * b1, e2 = a2 + t * b2, rel = c - t * d0;
    const vec3 normal = cross(e1, e2);
    const float area2 = dot(normal, normal);
    if (!(area2 > 0.0)) continue;
    const float w1 = dot(cross(rel, e2), normal) / area2, w2 = dot(cross(e1, rel), normal) / area2;
    const float w0 = 1.0 - w1 - w2;
    const float kEdge = -1e-6;  // rounding on an edge shared by two volumes
    if (w0 < kEdge || w1 < kEdge || w2 < kEdge) continue;
    const vec3 w = vec3(w0, w1, w2);
    const vec3 direction = normalize(w0 * d0 + w1 * d1 + w2 * d2);
    const vec3 start = w0 * p0 + w1 * p1 + w2 * p2;
    sum += beam_irradiance(t, w) * exp(-absorption * length(x - start)) * abs(dot(n, direction));
  }
  irradiance = vec4(sum, 0.0);
  if (sum.r > 0.0 || sum.g > 0.0 || sum.b > 0.0) counts.y = 1.0;
}
