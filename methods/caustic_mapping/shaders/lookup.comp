#version 450
// The lookup of one pass at every receiver pixel (light_pass.cpp's add_lookup): the shadow-map test, the
// caustic map's flux per texel measure read bilinearly, converted to irradiance on the surface; added to
// what the passes before it left (the first pass writes).
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Views { vec4 views[]; };
layout(std430, binding = 1) readonly buffer Receivers { vec4 receivers[]; };
layout(std430, binding = 2) readonly buffer Measures { float measures[]; };
layout(std430, binding = 3) readonly buffer Caustic { vec4 caustic[]; };
layout(std430, binding = 4) readonly buffer Positions { vec4 positions[]; };
layout(std430, binding = 5) readonly buffer Normals { vec4 normals[]; };
layout(std430, binding = 6) buffer Output { vec4 irradiance[]; };

layout(push_constant) uniform Parameters {
  uint pass;
  uint resolution;
  uint first_texel;
  uint pixel_count;
  uint first_pass;
} parameters;

#include "common.glsl"

vec3 density_at(int x, int y, int n) {
  const uint texel = parameters.first_texel + uint(y * n + x);
  const float measure = measures[texel];
  return measure > 0.0 ? caustic[texel].xyz / measure : vec3(0.0);
}

void main() {
  const uint pixel = gl_GlobalInvocationID.x;
  if (pixel >= parameters.pixel_count) return;
  vec3 sum = parameters.first_pass != 0u ? vec3(0.0) : irradiance[pixel].xyz;
  const vec4 position = positions[pixel];
  if (position.w != 0.0) {
    const View view = view_at(2u * parameters.pass);
    const int n = int(parameters.resolution);
    const vec3 point = position.xyz, normal = normals[pixel].xyz;
    vec3 at;
    if (project(view, point, at)) {
      const int texel = texel_of(at, n);
      if (sees(view, n, parameters.first_texel, at, texel, point, normal)) {
        const float cosine = abs(dot(normal, travel_at(view, point)));
        const float fx = clamp(at.x * float(n) - 0.5, 0.0, float(n) - 1.0);
        const float fy = clamp(at.y * float(n) - 0.5, 0.0, float(n) - 1.0);
        const int x0 = min(int(fx), max(n - 2, 0)), y0 = min(int(fy), max(n - 2, 0));
        const int x1 = min(x0 + 1, n - 1), y1 = min(y0 + 1, n - 1);
        const float wx = fx - float(x0), wy = fy - float(y0);
        const vec3 density = density_at(x0, y0, n) * ((1.0 - wx) * (1.0 - wy)) + density_at(x1, y0, n) * (wx * (1.0 - wy)) +
                             density_at(x0, y1, n) * ((1.0 - wx) * wy) + density_at(x1, y1, n) * (wx * wy);
        sum += density * (view.orthographic ? cosine : cosine / (at.z * at.z));
      }
    }
  }
  irradiance[pixel] = vec4(sum, 0.0);
}
