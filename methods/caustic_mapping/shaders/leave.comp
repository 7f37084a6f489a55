#version 450
// The leave stage of one pass: how each photon-buffer texel's photon leaves the object
// (light_pass.cpp's leave_object, step by step): reflected off a mirror, or refracted through glass at one
// interface or, with two interfaces, out of the back by Wyman's image-space approximation. Reads the
// rasterised photon buffer (front: position and object, normal and d_N; back: position and 1, normal)
// and writes per texel the photon record the photon stage reads: origin and status (0 leaves, 1 no
// photon, 2 its second interface failed); direction and 1 for one interface; flux and the luminance the
// method does not follow (glass's Fresnel reflection); the medium's absorption.
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Views { vec4 views[]; };
layout(std430, binding = 1) readonly buffer Objects { vec4 objects[]; };
layout(std430, binding = 2) readonly buffer Buffer { vec4 buffer_texels[]; };
layout(std430, binding = 3) readonly buffer Measures { float photon_measures[]; };
layout(std430, binding = 4) readonly buffer Strengths { vec4 strengths[]; };
layout(std430, binding = 5) writeonly buffer Photons { vec4 photons[]; };

layout(push_constant) uniform Parameters {
  uint pass;
  uint resolution;
  uint first_photon;
  uint object;
  uint refraction;  // 0 auto, 1 two_interface, 2 one_interface
} parameters;

#define NO_RECEIVER_MAP
#include "common.glsl"

const uint kObjectVec4 = 5u;
const float kLeaves = 0.0, kNoPhoton = 1.0, kSecondFailed = 2.0;

float luminance(vec3 c) { return dot(c, vec3(0.2126, 0.7152, 0.0722)); }

// core/optics.cpp's fresnel_dielectric and refract, and pbrt's conductor Fresnel per channel.
float fresnel_dielectric(float cos_incident, float eta) {
  cos_incident = clamp(cos_incident, 0.0, 1.0);
  const float sin2_transmitted = (1.0 - cos_incident * cos_incident) / (eta * eta);
  if (sin2_transmitted >= 1.0) return 1.0;
  const float cos_transmitted = sqrt(1.0 - sin2_transmitted);
  const float parallel = (eta * cos_incident - cos_transmitted) / (eta * cos_incident + cos_transmitted);
  const float perpendicular = (cos_incident - eta * cos_transmitted) / (cos_incident + eta * cos_transmitted);
  return 0.5 * (parallel * parallel + perpendicular * perpendicular);
}

float fresnel_conductor(float cos_i, float eta, float k) {
  const float cos2 = cos_i * cos_i, sin2 = 1.0 - cos2, eta2 = eta * eta, k2 = k * k;
  const float t0 = eta2 - k2 - sin2;
  const float a2plusb2 = sqrt(t0 * t0 + 4.0 * eta2 * k2);
  const float t1 = a2plusb2 + cos2;
  const float a = sqrt(max(0.0, 0.5 * (a2plusb2 + t0)));
  const float t2 = 2.0 * cos_i * a;
  const float rs = (t1 - t2) / (t1 + t2);
  const float t3 = cos2 * a2plusb2 + sin2 * sin2;
  const float t4 = t2 * sin2;
  const float rp = rs * (t3 - t4) / (t3 + t4);
  return 0.5 * (rp + rs);
}

bool refract_through(vec3 d, vec3 n, float eta, out vec3 transmitted) {
  const float cos_incident = -dot(d, n);
  const float sin2_transmitted = (1.0 - cos_incident * cos_incident) / (eta * eta);
  if (sin2_transmitted >= 1.0) return false;
  const float cos_transmitted = sqrt(1.0 - sin2_transmitted);
  transmitted = normalize(d / eta + (cos_incident / eta - cos_transmitted) * n);
  return true;
}

void write(uint slot, vec3 origin, float status, vec3 direction, bool one, vec3 flux, float not_modelled, vec3 absorption) {
  photons[4u * slot] = vec4(origin, status);
  photons[4u * slot + 1u] = vec4(direction, one ? 1.0 : 0.0);
  photons[4u * slot + 2u] = vec4(flux, not_modelled);
  photons[4u * slot + 3u] = vec4(absorption, 0.0);
}

void main() {
  const uint texel = gl_GlobalInvocationID.x;
  const uint n = parameters.resolution, texels = n * n;
  if (texel >= texels) return;
  const uint slot = parameters.first_photon + texel;
  const uint base = 4u * parameters.first_photon;  // the pass's front positions, front normals, backs, back normals
  const vec4 front = buffer_texels[base + texel];
  if (front.w != float(parameters.object)) {  // nothing, or another object in front: no photon
    write(slot, vec3(0.0), kNoPhoton, vec3(0.0), false, vec3(0.0), 0.0, vec3(0.0));
    return;
  }
  const vec4 front_normal = buffer_texels[base + texels + texel];
  const View view = view_at(2u * parameters.pass + 1u);
  const vec3 travel = travel_at(view, front.xyz);
  const vec3 flux_in = strengths[parameters.pass].xyz * photon_measures[slot];
  const vec3 normal = dot(travel, front_normal.xyz) < 0.0 ? front_normal.xyz : -front_normal.xyz;
  const float cos_incident = max(0.0, -dot(travel, normal));
  const uint material = kObjectVec4 * parameters.object;
  const vec4 kind = objects[material];  // kind (1 mirror, 2 glass, 3 diffuse mirror), receives, ior, conductor
  if (kind.x != 2.0) {
    vec3 reflectance = objects[material + 1u].xyz;
    if (kind.w != 0.0) {
      const vec3 eta = objects[material + 2u].xyz, k = objects[material + 3u].xyz;
      const float c = clamp(cos_incident, 0.0, 1.0);
      reflectance *= vec3(fresnel_conductor(c, eta.x, k.x), fresnel_conductor(c, eta.y, k.y), fresnel_conductor(c, eta.z, k.z));
    }
    write(slot, front.xyz, kLeaves, reflect(travel, normal), false, flux_in * reflectance, 0.0, vec3(0.0));
    return;
  }
  const float ior = kind.z;
  const vec3 absorption = objects[material + 4u].xyz;
  const float eta = dot(travel, front_normal.xyz) < 0.0 ? ior : 1.0 / ior;
  const float entering = fresnel_dielectric(cos_incident, eta);
  float not_modelled = luminance(flux_in) * entering;
  vec3 flux = flux_in * (1.0 - entering);
  vec3 inside;
  if (!refract_through(travel, normal, eta, inside)) {
    write(slot, front.xyz, kSecondFailed, vec3(0.0), false, flux, not_modelled, vec3(0.0));
    return;
  }
  const vec4 back = buffer_texels[base + 2u * texels + texel];
  const bool has_back = back.w != 0.0;
  if (parameters.refraction == 2u || (parameters.refraction == 0u && !has_back)) {
    write(slot, front.xyz, kLeaves, inside, true, flux, not_modelled, absorption);
    return;
  }
  // Wyman 2005: d = (t / i) d_V + (1 - t / i) d_N along the refracted ray; the exit normal read where it ends.
  vec3 front_at, back_at;
  if (!has_back || !project(view, front.xyz, front_at) || !project(view, back.xyz, back_at)) {
    write(slot, front.xyz, kSecondFailed, vec3(0.0), false, flux, not_modelled, vec3(0.0));
    return;
  }
  const float along_light = back_at.z - front_at.z;
  const float incident = acos(clamp(cos_incident, 0.0, 1.0));
  const float transmitted = acos(clamp(-dot(inside, normal), 0.0, 1.0));
  const float ratio = incident > 1e-4 ? transmitted / incident : 1.0 / ior;
  const float distance = ratio * along_light + (1.0 - ratio) * front_normal.w;
  const vec3 exit = front.xyz + inside * distance;
  vec3 exit_at;
  const int exit_texel = project(view, exit, exit_at) ? texel_of(exit_at, int(n)) : -1;
  if (exit_texel < 0 || buffer_texels[base + 2u * texels + uint(exit_texel)].w == 0.0) {
    write(slot, front.xyz, kSecondFailed, vec3(0.0), false, flux, not_modelled, vec3(0.0));
    return;
  }
  const vec3 back_normal = buffer_texels[base + 3u * texels + uint(exit_texel)].xyz;
  const vec3 facing = dot(inside, back_normal) < 0.0 ? back_normal : -back_normal;
  const float cos_inside = max(0.0, -dot(inside, facing));
  const float leaving = fresnel_dielectric(cos_inside, 1.0 / ior);
  const vec3 through = flux * exp(-absorption * distance);
  vec3 outside;
  if (!refract_through(inside, facing, 1.0 / ior, outside)) {  // total internal reflection: what reaches it is lost
    write(slot, front.xyz, kSecondFailed, vec3(0.0), false, through, not_modelled, vec3(0.0));
    return;
  }
  not_modelled += luminance(through) * leaving;
  write(slot, exit, kLeaves, outside, false, through * (1.0 - leaving), not_modelled, vec3(0.0));
}
