#version 450
// lpi's per-pixel lookup (Wyman 2003, Sections 3.2, 5.1 and 5.2) for storage grid and shells, one
// invocation per pixel: the arithmetic of methods/lpi/lookup.h (add_object_caustic), GridLayout::stencil,
// ShellLayout::stencil, SphericalMesh::locate and StoredValues::add, in the same order, so that the two
// backends differ by float rounding only. The frame's layout: methods/lpi/frame_data.h.
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer ReceiverPositions { vec4 receiver_positions[]; };
layout(std430, binding = 1) readonly buffer ReceiverNormals { vec4 receiver_normals[]; };
layout(std430, binding = 2) readonly buffer Objects { uint objects[]; };
layout(std430, binding = 3) readonly buffer Lights { float lights[]; };
layout(std430, binding = 4) readonly buffer Values { uint values[]; };
layout(std430, binding = 5) readonly buffer Scales { float scales[]; };
layout(std430, binding = 6) readonly buffer Shells { uint shells[]; };
layout(std430, binding = 7) writeonly buffer Output { vec4 irradiance[]; };

layout(push_constant) uniform Parameters {
  uint pixel_count;
  uint object_count;
  uint storage;    // 0 grid, 1 shells
  uint channels;   // 3 or 9
  uint value_type;  // 0 float32, 1 float16, 2 uint8, 3 signed uint8
  uint outside;    // 0 clamp, 1 fade, 2 zero
} params;

// Words of an object's record (lpi_record in frame_data.h).
const uint kLinear = 0u, kOffset = 9u, kNormals = 12u, kCenter = 21u, kRadius = 24u, kCount = 25u, kSpacing = 26u,
           kFirstLight = 27u, kLightCount = 28u, kValues = 29u, kPoints = 30u, kScales = 31u, kRadii = 32u,
           kTriangles = 33u, kTexels = 34u, kCandidates = 35u, kTableSize = 36u, kLongestEdge = 37u, kWords = 40u;
const uint kLightFloats = 40u, kFirstRead = 4u, kReadFloats = 12u;
// SphericalMesh::kEdgeTolerance.
const float kEdgeTolerance = 1.0 / 2097152.0;

uint record_base;  // the current object's first word

uint word(uint k) { return objects[record_base + k]; }
float real(uint k) { return uintBitsToFloat(objects[record_base + k]); }
vec3 vector3(uint k) { return vec3(real(k), real(k + 1u), real(k + 2u)); }
mat3 matrix3(uint k) { return mat3(vector3(k), vector3(k + 3u), vector3(k + 6u)); }
float shell_real(uint k) { return uintBitsToFloat(shells[k]); }

// half_to_float of stored_values.h: exact (a subnormal is its mantissa times 2^-24).
float half_value(uint bits) {
  uint sign = (bits & 0x8000u) << 16;
  uint exponent = (bits >> 10) & 0x1fu;
  uint mantissa = bits & 0x3ffu;
  if (exponent == 0u) {
    float magnitude = float(mantissa) * (1.0 / 16777216.0);
    return sign != 0u ? -magnitude : magnitude;
  }
  if (exponent == 31u) return uintBitsToFloat(sign | 0x7f800000u | (mantissa << 13));
  return uintBitsToFloat(sign | ((exponent + 112u) << 23) | (mantissa << 13));
}

// Element `element` of the current object's values, decoded as StoredValues::add reads it.
float stored(uint element) {
  uint first = word(kValues);
  if (params.value_type == 0u) return uintBitsToFloat(values[first + element]);
  if (params.value_type == 1u) {
    uint pair = values[first + element / 2u];
    return half_value((element & 1u) != 0u ? pair >> 16 : pair & 0xffffu);
  }
  uint quad = values[first + element / 4u];
  int shift = int(8u * (element & 3u));
  if (params.value_type == 2u) return float(bitfieldExtract(quad, shift, 8));
  return float(bitfieldExtract(int(quad), shift, 8));
}

// StoredValues::add: out += weight x the values of `point` of `light_sample`.
void add_point(uint light_sample, uint point, float weight, inout float out_values[9]) {
  uint first = (light_sample * word(kPoints) + point) * params.channels;
  float scaled = params.value_type >= 2u ? weight * scales[word(kScales) + light_sample] : weight;
  for (uint c = 0u; c < params.channels; ++c) out_values[c] += scaled * stored(first + c);
}

// GridLayout::stencil at `position`, each point added with its weight times `read_weight`.
void add_grid(vec3 position, uint light_sample, float read_weight, inout float out_values[9]) {
  int resolution = int(word(kCount));
  float cell = real(kSpacing);
  vec3 minimum = vector3(kCenter) - vec3(real(kRadius));
  int base[3];
  float fraction[3];
  for (int axis = 0; axis < 3; ++axis) {
    float local = (position[axis] - minimum[axis]) / cell - 0.5;
    local = clamp(local, 0.0, float(resolution - 1));
    base[axis] = min(int(local), max(0, resolution - 2));
    fraction[axis] = resolution > 1 ? local - float(base[axis]) : 0.0;
  }
  int corners = resolution > 1 ? 8 : 1;
  for (int corner = 0; corner < corners; ++corner) {
    int dx = corner & 1, dy = (corner >> 1) & 1, dz = (corner >> 2) & 1;
    float weight = (dx != 0 ? fraction[0] : 1.0 - fraction[0]) * (dy != 0 ? fraction[1] : 1.0 - fraction[1]) *
                   (dz != 0 ? fraction[2] : 1.0 - fraction[2]);
    uint point = uint((base[2] + dz) * resolution + base[1] + dy) * uint(resolution) + uint(base[0] + dx);
    add_point(light_sample, point, weight * read_weight, out_values);
  }
}

// SphericalMesh::texel_of.
uint texel_of(vec3 d, int n) {
  float ax = abs(d.x), ay = abs(d.y), az = abs(d.z);
  bool x_major = (ax >= ay) && (ax >= az), y_major = !x_major && (ay >= az);
  int axis = x_major ? 0 : (y_major ? 1 : 2);
  float major = x_major ? d.x : (y_major ? d.y : d.z);
  float u = x_major ? d.y : (y_major ? d.z : d.x);
  float v = x_major ? d.z : (y_major ? d.x : d.y);
  float scale = 0.5 * float(n) / abs(major);
  float fu = (u + abs(major)) * scale, fv = (v + abs(major)) * scale;
  int i = fu > 0.0 ? min(int(fu), n - 1) : 0;
  int j = fv > 0.0 ? min(int(fv), n - 1) : 0;
  int face = 2 * axis + (major < 0.0 ? 1 : 0);
  return uint((face * n + j) * n + i);
}

// SphericalMesh::inside, in float (the CPU's double side tests differ by rounding, and where they
// would pick the neighbouring triangle the opposite corner's weight is zero on both).
bool inside(uint triangle, vec3 d, out vec3 normal[3], out float side[3]) {
  uint at = word(kTriangles) + 12u * triangle;
  vec3 a = vec3(shell_real(at), shell_real(at + 1u), shell_real(at + 2u));
  vec3 b = vec3(shell_real(at + 3u), shell_real(at + 4u), shell_real(at + 5u));
  vec3 c = vec3(shell_real(at + 6u), shell_real(at + 7u), shell_real(at + 8u));
  normal[0] = cross(b, c);
  normal[1] = cross(c, a);
  normal[2] = cross(a, b);
  bool within = true;
  for (int e = 0; e < 3; ++e) {
    side[e] = dot(d, normal[e]);
    if (side[e] < 0.0 && side[e] * side[e] > kEdgeTolerance * kEdgeTolerance * dot(normal[e], normal[e])) within = false;
  }
  return within;
}

float ramp(vec3 normal, float side) {
  if (side >= 2.0 * kEdgeTolerance * real(kLongestEdge)) return side;
  float band = 2.0 * kEdgeTolerance * sqrt(dot(normal, normal));
  return side >= band ? side : (side > 0.5 * band ? 2.0 * (side - 0.5 * band) : 0.0);
}

// SphericalMesh::location_from: the corners' weights.
vec3 location_weights(vec3 normal[3], float side[3]) {
  float r0 = ramp(normal[0], side[0]), r1 = ramp(normal[1], side[1]), r2 = ramp(normal[2], side[2]);
  float total = r0 + r1 + r2;
  if (!(total > 0.0)) {
    int corner = side[0] >= side[1] ? (side[0] >= side[2] ? 0 : 2) : (side[1] >= side[2] ? 1 : 2);
    return vec3(corner == 0 ? 1.0 : 0.0, corner == 1 ? 1.0 : 0.0, corner == 2 ? 1.0 : 0.0);
  }
  float scale = 1.0 / total;
  float w0 = r0 * scale, w1 = r1 * scale, w2 = r2 * scale;
  if (w0 >= w1 && w0 >= w2) {
    w0 = 1.0 - (w1 + w2);
  } else if (w1 >= w2) {
    w1 = 1.0 - (w2 + w0);
  } else {
    w2 = 1.0 - (w0 + w1);
  }
  return vec3(w0, w1, w2);
}

// SphericalMesh::locate: the table's likeliest triangle, then its other candidates.
void locate(vec3 d, out uint triangle, out vec3 weights) {
  uint texel = word(kTexels) + 2u * texel_of(d, int(word(kTableSize)));
  vec3 normal[3];
  float side[3];
  triangle = shells[texel];
  if (inside(triangle, d, normal, side)) {
    weights = location_weights(normal, side);
    return;
  }
  uint best = triangle;
  vec3 best_normal[3] = normal;
  float best_side[3] = side;
  uint candidates = word(kCandidates);
  for (uint k = shells[texel + 1u]; k < shells[texel + 3u]; ++k) {
    uint candidate = shells[candidates + k];
    if (inside(candidate, d, normal, side)) {
      triangle = candidate;
      weights = location_weights(normal, side);
      return;
    }
    if (min(side[0], min(side[1], side[2])) > min(best_side[0], min(best_side[1], best_side[2]))) {
      best = candidate;
      best_normal = normal;
      best_side = side;
    }
  }
  triangle = best;
  weights = location_weights(best_normal, best_side);
}

// ShellLayout::stencil at `position`, each point added with its weight times `read_weight`.
void add_shells(vec3 position, uint light_sample, float read_weight, inout float out_values[9]) {
  vec3 offset = position - vector3(kCenter);
  float r = length(offset);
  vec3 direction = r > 0.0 ? offset / r : vec3(0.0, 1.0, 0.0);
  uint triangle;
  vec3 weights;
  locate(direction, triangle, weights);
  uint at = word(kTriangles) + 12u * triangle + 9u;
  uint corners[3] = uint[3](shells[at], shells[at + 1u], shells[at + 2u]);
  // radial_interval: how many radii are <= r (std::upper_bound).
  int shell_count = int(word(kCount));
  uint radii = word(kRadii);
  int low = 0, high = shell_count;
  while (low < high) {
    int middle = (low + high) / 2;
    if (shell_real(radii + uint(middle)) <= r) low = middle + 1; else high = middle;
  }
  int interval = min(low, shell_count);
  float radial_upper = 1.0;
  if (interval == shell_count) {
    interval = shell_count - 1;
  } else if (interval > 0) {
    float lower = shell_real(radii + uint(interval - 1)), upper = shell_real(radii + uint(interval));
    radial_upper = clamp((r - lower) / (upper - lower), 0.0, 1.0);
  }
  uint directions = word(kSpacing);
  for (int corner = 0; corner < 3; ++corner) {
    add_point(light_sample, uint(interval) * directions + corners[corner], weights[corner] * radial_upper * read_weight,
              out_values);
    if (interval > 0 && radial_upper < 1.0) {
      add_point(light_sample, uint(interval - 1) * directions + corners[corner],
                weights[corner] * (1.0 - radial_upper) * read_weight, out_values);
    }
  }
}

// add_shading of lookup.h.
void add_shading(float read_values[9], vec3 normal, float paper_cosine, inout vec3 sums) {
  if (params.channels == 3u) {
    for (int c = 0; c < 3; ++c) sums[c] += read_values[c] * paper_cosine;
  } else {
    for (int c = 0; c < 3; ++c) {
      sums[c] += normal.x * read_values[3 * c] + normal.y * read_values[3 * c + 1] + normal.z * read_values[3 * c + 2];
    }
  }
}

void main() {
  uint pixel = gl_GlobalInvocationID.x;
  if (pixel >= params.pixel_count) return;
  vec4 receiver = receiver_positions[pixel];
  vec3 result = vec3(0.0);
  if (receiver.w != 0.0) {
    for (uint object = 0u; object < params.object_count; ++object) {
      record_base = object * kWords;
      vec3 point = matrix3(kLinear) * receiver.xyz + vector3(kOffset);
      vec3 normal = normalize(matrix3(kNormals) * receiver_normals[pixel].xyz);
      vec3 center = vector3(kCenter);
      float radius = real(kRadius);
      vec3 offset = point - center;
      float distance = length(offset);
      float fade = 1.0;
      if (distance > radius) {
        if (params.outside == 2u) continue;
        if (params.outside == 1u) fade = (radius / distance) * (radius / distance);
        offset *= radius / distance;  // the value on the ball's surface
      }
      float paper_cosine = distance > 0.0 ? max(0.0, -dot(normal, point - center) / distance) : 0.0;
      vec3 total = vec3(0.0);
      uint last_light = word(kFirstLight) + word(kLightCount);
      for (uint light = word(kFirstLight); light < last_light; ++light) {
        uint base = light * kLightFloats;
        vec3 sums = vec3(0.0);
        int reads = int(lights[base + 3u]);
        for (int r = 0; r < reads; ++r) {
          uint at = base + kFirstRead + uint(r) * kReadFloats;
          uint light_sample = uint(lights[at]);
          float weight = lights[at + 1u];
          bool rotated = lights[at + 2u] != 0.0;
          mat3 rotation = mat3(lights[at + 3u], lights[at + 4u], lights[at + 5u], lights[at + 6u], lights[at + 7u],
                               lights[at + 8u], lights[at + 9u], lights[at + 10u], lights[at + 11u]);
          vec3 position = center + (rotated ? rotation * offset : offset);
          float read_values[9] = float[9](0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
          if (params.storage == 0u) {
            add_grid(position, light_sample, weight, read_values);
          } else {
            add_shells(position, light_sample, weight, read_values);
          }
          // Vector irradiance read at R p is R E(p): dot it with R n.
          add_shading(read_values, rotated ? rotation * normal : normal, paper_cosine, sums);
        }
        vec3 light_irradiance = vec3(lights[base], lights[base + 1u], lights[base + 2u]);
        for (int c = 0; c < 3; ++c) total[c] += max(0.0, sums[c]) * light_irradiance[c] * fade;
      }
      result += total;
    }
  }
  irradiance[pixel] = vec4(result, 0.0);
}
