#version 450
// pinhole (Wand & Strasser 2003) on Vulkan: one invocation per receiver pixel sums the light that every
// reflector sample projects onto it. The same arithmetic as the CPU backend (methods/pinhole/pinhole.cpp,
// LightCubeMap::lookup_texel), so that both agree to float rounding.
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer ReceiverPositions { vec4 receiver_position[]; };
layout(std430, binding = 1) readonly buffer ReceiverNormals { vec4 receiver_normal[]; };
layout(std430, binding = 2) readonly buffer SamplePositions { vec4 sample_position[]; };
layout(std430, binding = 3) readonly buffer SampleNormals { vec4 sample_normal[]; };
layout(std430, binding = 4) readonly buffer Materials { vec4 material[]; };
layout(std430, binding = 5) readonly buffer CubeMap { float texel[]; };
layout(std430, binding = 6) writeonly buffer Irradiance { vec4 irradiance[]; };

layout(push_constant) uniform Parameters {
  uint pixel_count;
  uint sample_count;
  int resolution;
  float epsilon;
  float area;
  uint attenuation;
  uint fresnel;
  uint refraction;  // 0 reflect, 1 refract, 2 auto: glass refracts (material kind 2), the others reflect
  float footprint_radius;
  uint filtering;  // 1 isotropic, 2 anisotropic (the own filter; the hardware sampler is made for one)
} p;

#if defined(FILTERED) || defined(OWN_FILTER)
// Differential point samples (Section 3.3): per sample the two principal directions and the normal's
// derivative along each.
layout(std430, binding = 7) readonly buffer Differentials { vec4 differential[]; };
#endif
#ifdef FILTERED
// The light map as a mip-mapped cube texture for textureGrad (filter_implementation: hardware).
layout(binding = 8) uniform samplerCube light_map;
#endif
#ifdef OWN_FILTER
// The method's own filter (methods/pinhole/cube_filter.cpp, README "The filter"), probe by probe on the
// same texels: CubeFilter::texels(), every level's faces with a border of one texel, RGB.
layout(std430, binding = 8) readonly buffer FilterLevels { float level_texel[]; };
int level_count;
int level_size[16];
uint level_offset[16];

void setup_levels() {
  int size = p.resolution;
  uint offset = 0u;
  level_count = 0;
  for (int k = 0; k < 16; ++k) {
    level_size[k] = size;
    level_offset[k] = offset;
    level_count = k + 1;
    offset += uint(6 * (size + 2) * (size + 2) * 3);
    if (size == 1) break;
    size = max(1, size / 2);
  }
}

const vec3 face_s[6] = vec3[6](vec3(0, 0, -1), vec3(0, 0, 1), vec3(1, 0, 0), vec3(1, 0, 0), vec3(1, 0, 0), vec3(-1, 0, 0));
const vec3 face_t[6] = vec3[6](vec3(0, -1, 0), vec3(0, -1, 0), vec3(0, 0, 1), vec3(0, 0, -1), vec3(0, -1, 0), vec3(0, -1, 0));
const vec3 face_m[6] = vec3[6](vec3(1, 0, 0), vec3(-1, 0, 0), vec3(0, 1, 0), vec3(0, -1, 0), vec3(0, 0, 1), vec3(0, 0, -1));

int face_of(vec3 d) {
  vec3 a = abs(d);
  if (a.x >= a.y && a.x >= a.z) return d.x > 0.0 ? 0 : 1;
  if (a.y >= a.z) return d.y > 0.0 ? 2 : 3;
  return d.z > 0.0 ? 4 : 5;
}

vec3 level_fetch(uint at) { return vec3(level_texel[at], level_texel[at + 1u], level_texel[at + 2u]); }

vec3 filter_bilinear(int level, vec3 d) {
  int size = level_size[level];
  int face = face_of(d);
  float major = dot(face_m[face], d);
  float resolution = float(size);
  float scale = 0.5 * resolution / major;
  float s = dot(face_s[face], d) * scale + 0.5 * resolution, t = dot(face_t[face], d) * scale + 0.5 * resolution;
  float fx = min(max(s - 0.5, -1.0), resolution - 0.5), fy = min(max(t - 0.5, -1.0), resolution - 0.5);
  float x0 = floor(fx), y0 = floor(fy);
  float wx = fx - x0, wy = fy - y0;
  int side = size + 2;
  uint at = level_offset[level] + uint(((face * side + int(y0) + 1) * side + int(x0) + 1) * 3);
  uint row = uint(side * 3);
  return mix(mix(level_fetch(at), level_fetch(at + 3u), wx), mix(level_fetch(at + row), level_fetch(at + row + 3u), wx), wy);
}

vec3 filter_trilinear(vec3 d, float level) {
  int finer = int(level);
  float fraction = level - float(finer);
  vec3 result = filter_bilinear(finer, d);
  if (fraction > 0.0 && finer + 1 < level_count) result = mix(result, filter_bilinear(finer + 1, d), fraction);
  return result;
}

vec3 own_filter(vec3 d, vec3 gradient_u, vec3 gradient_v) {
  int face = face_of(d);
  float major = dot(face_m[face], d);
  float u = dot(face_s[face], d) / major, v = dot(face_t[face], d) / major;
  float half_size = 0.5 * float(p.resolution) / major;
  float along = dot(face_m[face], gradient_u);
  vec2 texels_u = vec2(dot(face_s[face], gradient_u) - u * along, dot(face_t[face], gradient_u) - v * along) * half_size;
  along = dot(face_m[face], gradient_v);
  vec2 texels_v = vec2(dot(face_s[face], gradient_v) - u * along, dot(face_t[face], gradient_v) - v * along) * half_size;
  float length_u = sqrt(dot(texels_u, texels_u)), length_v = sqrt(dot(texels_v, texels_v));
  float top = float(level_count - 1);
  if (p.filtering == 1u) return filter_trilinear(d, min(log2(max(max(length_u, length_v), 1.0)), top));
  bool u_longer = length_u >= length_v;
  float longer = max(length_u, length_v), shorter = min(length_u, length_v);
  float ratio = min(ceil(longer / max(shorter, 1.0)), 16.0);
  int count = ratio >= 1.0 ? int(ratio) : 1;
  float level = min(log2(max(max(shorter, longer / float(count)), 1.0)), top);
  if (count == 1) return filter_trilinear(d, level);
  vec3 edge = u_longer ? gradient_u : gradient_v;
  vec3 step = edge / float(count), first = edge * (0.5 / float(count) - 0.5);
  vec3 sum = vec3(0.0);
  for (int i = 0; i < count; ++i) sum += filter_trilinear(d + first + float(i) * step, level);
  return sum * (1.0 / float(count));
}
#endif

float fresnel_dielectric(float cos_incident, float eta) {
  cos_incident = clamp(cos_incident, 0.0, 1.0);
  float sin2 = (1.0 - cos_incident * cos_incident) / (eta * eta);
  if (sin2 >= 1.0) return 1.0;
  float cos_t = sqrt(1.0 - sin2);
  float parallel = (eta * cos_incident - cos_t) / (eta * cos_incident + cos_t);
  float perpendicular = (cos_incident - eta * cos_t) / (cos_incident + eta * cos_t);
  return 0.5 * (parallel * parallel + perpendicular * perpendicular);
}

float fresnel_conductor(float cos_i, float eta, float k) {
  cos_i = clamp(cos_i, 0.0, 1.0);
  float cos2 = cos_i * cos_i, sin2 = 1.0 - cos2, eta2 = eta * eta, k2 = k * k;
  float t0 = eta2 - k2 - sin2;
  float a2plusb2 = sqrt(t0 * t0 + 4.0 * eta2 * k2);
  float t1 = a2plusb2 + cos2;
  float a = sqrt(max(0.0, 0.5 * (a2plusb2 + t0)));
  float t2 = 2.0 * cos_i * a;
  float rs = (t1 - t2) / (t1 + t2);
  float t3 = cos2 * a2plusb2 + sin2 * sin2;
  float t4 = t2 * sin2;
  float rp = rs * (t3 - t4) / (t3 + t4);
  return 0.5 * (rp + rs);
}

vec3 fetch(int face, int x, int y) {
  int index = ((face * p.resolution + y) * p.resolution + x) * 3;
  return vec3(texel[index], texel[index + 1], texel[index + 2]);
}

vec3 cube_lookup(vec3 d) {
  vec3 a = abs(d);
  float major, sc, tc;
  int face;
  if (a.x >= a.y && a.x >= a.z) {
    face = d.x > 0.0 ? 0 : 1; major = a.x; sc = d.x > 0.0 ? -d.z : d.z; tc = -d.y;
  } else if (a.y >= a.z) {
    face = d.y > 0.0 ? 2 : 3; major = a.y; sc = d.x; tc = d.y > 0.0 ? d.z : -d.z;
  } else {
    face = d.z > 0.0 ? 4 : 5; major = a.z; sc = d.z > 0.0 ? d.x : -d.x; tc = -d.y;
  }
  float resolution = float(p.resolution);
  float scale = 0.5 * resolution / major;
  float s = sc * scale + 0.5 * resolution, t = tc * scale + 0.5 * resolution;
  float fx = clamp(s - 0.5, 0.0, resolution - 1.0), fy = clamp(t - 0.5, 0.0, resolution - 1.0);
  int x0 = int(fx), y0 = int(fy);
  int x1 = min(x0 + 1, p.resolution - 1), y1 = min(y0 + 1, p.resolution - 1);
  float wx = fx - float(x0), wy = fy - float(y0);
  return mix(mix(fetch(face, x0, y0), fetch(face, x1, y0), wx), mix(fetch(face, x0, y1), fetch(face, x1, y1), wx), wy);
}

bool refract_direction(vec3 d, vec3 n, float eta, out vec3 transmitted) {
  float cos_incident = -dot(d, n);
  float sin2 = (1.0 - cos_incident * cos_incident) / (eta * eta);
  if (sin2 >= 1.0) return false;
  float cos_t = sqrt(1.0 - sin2);
  transmitted = normalize(d / eta + (cos_incident / eta - cos_t) * n);
  return true;
}

// Direction towards the light seen through a sample from a receiver in `direction`, and the cosine at
// the sample (methods/pinhole/pinhole.cpp, light_direction).
bool light_direction(vec3 direction, vec3 n, bool two_sided, float ior, bool refracts, out vec3 to_light,
                     out float cos_sample) {
  cos_sample = refracts ? dot(n, direction) : -dot(n, direction);
  to_light = vec3(0.0);
  if (cos_sample <= 0.0) {
    if (!two_sided) return false;
    n = -n;
    cos_sample = -cos_sample;
  }
  if (!refracts) {
    to_light = direction - 2.0 * dot(direction, n) * n;
    return true;
  }
  return refract_direction(direction, -n, 1.0 / ior, to_light);
}

void main() {
  uint pixel = gl_GlobalInvocationID.x;
  if (pixel >= p.pixel_count) return;
  vec4 receiver = receiver_position[pixel];
  if (receiver.w == 0.0) {
    irradiance[pixel] = vec4(0.0);
    return;
  }
  vec3 x = receiver.xyz, receiver_n = receiver_normal[pixel].xyz;
#ifdef OWN_FILTER
  setup_levels();
#endif
  vec3 sum = vec3(0.0);
  for (uint i = 0u; i < p.sample_count; ++i) {
    vec4 position = sample_position[i];
    vec4 normal_and_material = sample_normal[i];
    vec3 offset = position.xyz - x;
    float distance2 = dot(offset, offset);
    if (dot(receiver_n, offset) <= 0.0) continue;
    vec3 direction = offset * (1.0 / sqrt(distance2));
    float cos_receiver = dot(receiver_n, direction);
    int m = int(normal_and_material.w) * 3;
    vec4 m0 = material[m], m1 = material[m + 1], m2 = material[m + 2];
    const bool refracts = p.refraction == 1u || (p.refraction == 2u && m0.w == 2.0);
    vec3 to_light;
    float cos_sample;
    if (!light_direction(direction, normal_and_material.xyz, position.w >= 0.5, m1.w, refracts, to_light, cos_sample))
      continue;
#if defined(FILTERED) || defined(OWN_FILTER)
    // The footprint's gradients: light directions at p + r u and p + r v with normals n + r dn/du, n + r dn/dv.
    vec3 gradient[2];
    for (int k = 0; k < 2; ++k) {
      vec3 moved = position.xyz + p.footprint_radius * differential[4u * i + uint(k)].xyz - x;
      vec3 moved_normal = normalize(normal_and_material.xyz + p.footprint_radius * differential[4u * i + 2u + uint(k)].xyz);
      vec3 moved_light;
      float unused;
      gradient[k] = light_direction(normalize(moved), moved_normal, position.w >= 0.5, m1.w, refracts, moved_light, unused)
                        ? moved_light - to_light : vec3(0.0);
    }
#ifdef OWN_FILTER
    vec3 radiance = own_filter(to_light, gradient[0], gradient[1]);
#else
    vec3 radiance = textureGrad(light_map, to_light, gradient[0], gradient[1]).rgb;
#endif
#else
    vec3 radiance = cube_lookup(to_light);
#endif
    if (radiance.r + radiance.g + radiance.b <= 0.0) continue;
    float cosine = p.fresnel != 0u ? cos_sample : 1.0;
    vec3 throughput;
    if (refracts) {
      throughput = vec3((1.0 - fresnel_dielectric(cosine, 1.0 / m1.w)) * m1.w * m1.w);
    } else if (m0.w == 2.0) {
      throughput = vec3(fresnel_dielectric(cosine, m1.w));
    } else if (m0.w == 1.0) {
      throughput = m0.rgb * vec3(fresnel_conductor(cosine, m1.r, m2.r), fresnel_conductor(cosine, m1.g, m2.g),
                                 fresnel_conductor(cosine, m1.b, m2.b));
    } else {
      throughput = m0.rgb;
    }
    float geometry = p.attenuation != 0u ? cos_sample * cos_receiver / (distance2 + p.epsilon) : 1.0;
    sum += radiance * throughput * (geometry * p.area);
  }
  irradiance[pixel] = vec4(sum, 0.0);
}
