// Fresnel equations and the laws of reflection and refraction.
#pragma once

#include "core/math.h"

namespace causticbench {

// Unpolarized Fresnel reflectance of a dielectric interface. cos_incident is the cosine between the
// incoming ray (reversed) and the normal on the incident side (>= 0); eta = n_transmitted / n_incident.
// Returns 1 under total internal reflection.
float fresnel_dielectric(float cos_incident, float eta);

// Unpolarized Fresnel reflectance of a conductor with complex index eta + i k (relative to the outside
// medium), per colour channel.
Color fresnel_conductor(float cos_incident, const Color& eta, const Color& k);

// Refraction of incoming direction d (unit, towards the surface) through a surface with normal n that
// faces the incident side (dot(d, n) < 0); eta = n_transmitted / n_incident. Returns false under total
// internal reflection.
bool refract(const Vec3& d, const Vec3& n, float eta, Vec3& transmitted);

}  // namespace causticbench
