#version 450
// prt's per-frame product (Sloan, Kautz & Snyder 2002, Section 7): l = M L for every row of one object's
// transfer matrices, one invocation a row (cell, colour, incident coefficient), the bands^2-long dot
// product summed in the order methods/prt/transfer.cpp's incident_field sums it (eight partial sums s_r
// over j = r mod 8, folded as ((s0 + s4) + (s2 + s6)) + ((s1 + s5) + (s3 + s7))), so that the backends
// differ by rounding only. The frame's layout: methods/prt/frame_data.h.
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Objects { uint objects[]; };
layout(std430, binding = 1) readonly buffer Lighting { float lighting[]; };
layout(std430, binding = 2) readonly buffer Matrices { uint matrices[]; };
layout(std430, binding = 3) buffer Incident { float incident[]; };

layout(push_constant) uniform Parameters {
  uint object;
  uint rows;        // cells x 3 x bands^2
  uint coefficients;  // bands^2
  uint storage;     // 0 float32, 1 float16
  uint stride;      // invocations dispatched: rows beyond them are taken in turn (grid-stride)
} params;

// Words of an object's record (prt_record in frame_data.h).
const uint kMatrices = 27u, kLighting = 28u, kIncident = 29u, kWords = 32u;

// half_to_float of methods/common/stored_values.h, as lpi.comp decodes it: exact, subnormals included.
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

float entry(uint element) {
  if (params.storage == 0u) return uintBitsToFloat(matrices[element]);
  uint pair = matrices[element >> 1];
  return half_value((element & 1u) != 0u ? pair >> 16 : pair & 0xffffu);
}

void main() {
  uint base = params.object * kWords;
  uint n2 = params.coefficients;
  for (uint row = gl_GlobalInvocationID.x; row < params.rows; row += params.stride) {
    uint colour = (row / n2) % 3u;
    uint first = objects[base + kMatrices] + row * n2;
    uint light = objects[base + kLighting] + colour * n2;
    float s[8] = float[8](0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    for (uint j = 0u; j < n2; ++j) s[j & 7u] += entry(first + j) * lighting[light + j];
    incident[objects[base + kIncident] + row] = ((s[0] + s[4]) + (s[2] + s[6])) + ((s[1] + s[5]) + (s[3] + s[7]));
  }
}
