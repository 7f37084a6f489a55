#version 450
// prt's per-pixel lookup: each object's incident field (product.comp's l = M L) interpolated trilinearly
// at the receiver's build-space point, then the clamped-cosine sum over the bands at its normal, negative
// sums clamped to 0: the arithmetic of methods/prt/transfer.cpp (transfer_irradiance), GridLayout::stencil
// and spherical_harmonics.cpp's basis recurrence, in the same order, with the CPU's float tables, so that
// the backends differ by rounding only. The frame's layout: methods/prt/frame_data.h.
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer ReceiverPositions { vec4 receiver_positions[]; };
layout(std430, binding = 1) readonly buffer ReceiverNormals { vec4 receiver_normals[]; };
layout(std430, binding = 2) readonly buffer Objects { uint objects[]; };
layout(std430, binding = 3) readonly buffer Incident { float incident[]; };
layout(std430, binding = 4) readonly buffer BasisFactors { float factors[]; };
layout(std430, binding = 5) readonly buffer ClampedCosines { float cosines[]; };
layout(std430, binding = 6) writeonly buffer Output { vec4 irradiance[]; };

layout(push_constant) uniform Parameters {
  uint pixel_count;
  uint object_count;
  uint bands;
} params;

// Words of an object's record (prt_record in frame_data.h).
const uint kLinear = 0u, kOffset = 9u, kNormals = 12u, kCenter = 21u, kHalf = 24u, kResolution = 25u, kCell = 26u,
           kIncident = 29u, kWords = 32u;
const uint kMaxCoefficients = 100u;

uint record_base;

uint word(uint k) { return objects[record_base + k]; }
float real(uint k) { return uintBitsToFloat(objects[record_base + k]); }
vec3 vector3(uint k) { return vec3(real(k), real(k + 1u), real(k + 2u)); }
mat3 matrix3(uint k) { return mat3(vector3(k), vector3(k + 3u), vector3(k + 6u)); }

uint coefficient_index(uint l, int m) { return uint(int(l * l + l) + m); }

// spherical_harmonics.cpp's evaluate_basis in float: the associated Legendre recurrence in z times the
// real and imaginary parts of (x + i y)^m.
void evaluate(vec3 d, inout float basis[kMaxCoefficients]) {
  uint n2 = params.bands * params.bands;
  float cosine = 1.0, sine = 0.0;
  for (uint m = 0u; m < params.bands; ++m) {
    float before = 0.0, current = 1.0;
    for (uint l = m; l < params.bands; ++l) {
      if (l > m) {
        uint k = coefficient_index(l, int(m));
        float next = factors[n2 + k] * d.z * current - factors[2u * n2 + k] * before;
        before = current;
        current = next;
      }
      float radial = factors[coefficient_index(l, int(m))] * current;
      if (m == 0u) {
        basis[coefficient_index(l, 0)] = radial;
      } else {
        basis[coefficient_index(l, int(m))] = radial * cosine;
        basis[coefficient_index(l, -int(m))] = radial * sine;
      }
    }
    float next_cosine = d.x * cosine - d.y * sine;
    sine = d.x * sine + d.y * cosine;
    cosine = next_cosine;
  }
}

// transfer_irradiance for the current object: zero outside its cube.
vec3 object_irradiance(vec3 point, vec3 normal) {
  vec3 center = vector3(kCenter);
  float half_side = real(kHalf);
  vec3 offset = point - center;
  if (abs(offset.x) > half_side || abs(offset.y) > half_side || abs(offset.z) > half_side) return vec3(0.0);
  int resolution = int(word(kResolution));
  float cell = real(kCell);
  vec3 minimum = center - vec3(half_side);
  // GridLayout::stencil (resolution >= 2: eight corners, x lowest, weights (x y) z).
  int base[3];
  float fraction[3];
  for (int axis = 0; axis < 3; ++axis) {
    float local = (point[axis] - minimum[axis]) / cell - 0.5;
    local = clamp(local, 0.0, float(resolution - 1));
    base[axis] = min(int(local), resolution - 2);
    fraction[axis] = local - float(base[axis]);
  }
  uint n2 = params.bands * params.bands;
  uint values = 3u * n2;
  float coefficients[3u * kMaxCoefficients];
  for (uint k = 0u; k < values; ++k) coefficients[k] = 0.0;
  uint row = uint(resolution), slice = row * row;
  uint first = (uint(base[2]) * row + uint(base[1])) * row + uint(base[0]);
  for (int corner = 0; corner < 8; ++corner) {
    int dx = corner & 1, dy = (corner >> 1) & 1, dz = (corner >> 2) & 1;
    float xy = (dx != 0 ? fraction[0] : 1.0 - fraction[0]) * (dy != 0 ? fraction[1] : 1.0 - fraction[1]);
    float weight = xy * (dz != 0 ? fraction[2] : 1.0 - fraction[2]);
    uint point_index = first + uint(dz) * slice + uint(dy) * row + uint(dx);
    uint at = word(kIncident) + point_index * values;
    for (uint k = 0u; k < values; ++k) coefficients[k] += weight * incident[at + k];
  }
  float basis[kMaxCoefficients];
  evaluate(normal, basis);
  vec3 result = vec3(0.0);
  for (uint l = 0u; l < params.bands; ++l) {
    float cosine = cosines[l];
    if (cosine == 0.0) continue;
    for (int m = -int(l); m <= int(l); ++m) {
      uint k = coefficient_index(l, m);
      for (uint c = 0u; c < 3u; ++c) result[c] += cosine * coefficients[c * n2 + k] * basis[k];
    }
  }
  return max(result, vec3(0.0));
}

void main() {
  uint pixel = gl_GlobalInvocationID.x;
  if (pixel >= params.pixel_count) return;
  vec4 position = receiver_positions[pixel];
  if (position.w == 0.0) {
    irradiance[pixel] = vec4(0.0);
    return;
  }
  vec3 total = vec3(0.0);
  for (uint object = 0u; object < params.object_count; ++object) {
    record_base = object * kWords;
    vec3 point = matrix3(kLinear) * position.xyz + vector3(kOffset);
    vec3 normal = normalize(matrix3(kNormals) * receiver_normals[pixel].xyz);
    total += object_irradiance(point, normal);
  }
  irradiance[pixel] = vec4(total, 0.0);
}
