#version 450
// The photon stage of one pass: each photon leaving its object searches the receiver map in image space
// (Shah et al.; methods/caustic_mapping/receiver_search.cpp step by step), takes its hit on the found
// receiver's plane or at that receiver, and lands where the caustic map's window holds it and the light
// sees it. Writes per photon (x, y in caustic-map texels, Landing, receiver-map reads) and the flux
// arriving (after the medium's absorption). A photon-buffer texel that sent no photon (the leave stage's
// status, origin.w, not 0) lands nowhere.
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Views { vec4 views[]; };
layout(std430, binding = 1) readonly buffer Receivers { vec4 receivers[]; };
layout(std430, binding = 2) readonly buffer Photons { vec4 photons[]; };
layout(std430, binding = 3) writeonly buffer Landings { vec4 landings[]; };
layout(std430, binding = 4) writeonly buffer Arriving { vec4 arriving[]; };

layout(push_constant) uniform Parameters {
  uint pass;
  uint resolution;
  uint first_texel;
  uint first_photon;
  uint photon_count;
  uint iterations;
  uint plane_hit;
} parameters;

#include "common.glsl"

const float kLanded = 0.0, kSearchFailed = 1.0, kOutsideMap = 2.0, kNone = 3.0;

// The texel of the receiver the map holds where `point` projects, or -1.
int receiver_at(View view, int n, vec3 point) {
  vec3 projected;
  if (!project(view, point, projected)) return -1;
  const int texel = texel_of(projected, n);
  if (texel < 0 || isinf(receiver_position(parameters.first_texel, texel).w)) return -1;
  return texel;
}

void main() {
  const uint index = gl_GlobalInvocationID.x;
  if (index >= parameters.photon_count) return;
  const uint photon = parameters.first_photon + index;
  if (photons[4u * photon].w != 0.0) {
    landings[photon] = vec4(0.0, 0.0, kNone, 0.0);
    arriving[photon] = vec4(0.0);
    return;
  }
  const vec3 origin = photons[4u * photon].xyz, direction = photons[4u * photon + 1u].xyz;
  const vec3 flux = photons[4u * photon + 2u].xyz, absorption = photons[4u * photon + 3u].xyz;
  const View view = view_at(2u * parameters.pass);
  const int n = int(parameters.resolution);
  const uint first = parameters.first_texel;
  float steps = 1.0;
  int texel = receiver_at(view, n, origin);
  for (uint iteration = 0u; texel >= 0 && iteration < parameters.iterations; ++iteration) {
    const float distance = length(receiver_position(first, texel).xyz - origin);
    texel = receiver_at(view, n, origin + direction * distance);
    steps += 1.0;
  }
  if (texel < 0) {
    landings[photon] = vec4(0.0, 0.0, kSearchFailed, steps);
    arriving[photon] = vec4(0.0);
    return;
  }
  // Converged when the receiver found lies on the ray within what a texel spans on it.
  const vec4 found = receiver_position(first, texel);
  const vec3 receiver = found.xyz, normal = receiver_normal(first, n, texel);
  const vec3 offset = receiver - origin;
  const float along = dot(offset, direction);
  const float off_ray = length(offset - direction * along);
  const float facing = max(0.05, abs(dot(normal, travel_at(view, receiver))));
  const float tolerance = texel_side(view, n, found.w) * (1.0 + 1.0 / facing);
  if (along <= 0.0 || off_ray > tolerance) {
    landings[photon] = vec4(0.0, 0.0, kSearchFailed, steps);
    arriving[photon] = vec4(0.0);
    return;
  }
  vec3 hit = receiver;
  if (parameters.plane_hit != 0u) {
    const float facing_ray = dot(direction, normal);
    if (abs(facing_ray) > 1e-3) {
      const float distance = dot(receiver - origin, normal) / facing_ray;
      if (distance > 0.0) hit = origin + direction * distance;
    }
  }
  const vec3 arrives = flux * exp(-absorption * length(hit - origin));
  arriving[photon] = vec4(arrives, 0.0);
  vec3 at;
  const bool projected = project(view, hit, at);
  const int map_texel = projected ? texel_of(at, n) : -1;
  if (map_texel < 0 || !sees(view, n, first, at, map_texel, hit, receiver_normal(first, n, map_texel))) {
    landings[photon] = vec4(0.0, 0.0, kOutsideMap, steps);
    return;
  }
  landings[photon] = vec4(at.x * float(n), at.y * float(n), kLanded, steps);
}
