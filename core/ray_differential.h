// Ray differentials (Igehy 1999, "Tracing Ray Differentials"): how a ray's origin and direction change
// with two parameters of its emission (u and v: the coordinates of an emission texel), carried through
// transfer to a surface, reflection and refraction. A photon that stands for a texel of du x dv then
// covers, where it lands, the parallelogram spanned by dp_du du and dp_dv dv: the footprint a splatting
// method gives it (methods/rt_photons). The curvature enters through the shading normal's change along
// the surface (Tracer::shading_normal_change), so a focusing surface shrinks the footprint and a
// diverging one spreads it, to first order.
#pragma once

#include "core/math.h"

namespace causticbench {

struct RayDifferential {
  Vec3 dp_du{0.0f}, dp_dv{0.0f};  // the origin's (after transfer: the hit's) derivatives
  Vec3 dd_du{0.0f}, dd_dv{0.0f};  // the unit direction's derivatives
};

// From the ray's origin along unit direction d to the plane of normal n (any orientation) at distance t:
// dp' = dp + t dd + dt d, with dt = -(dp + t dd) . n / (d . n), so that dp' lies in the plane.
void transfer_differential(RayDifferential& differential, const Vec3& d, float t, const Vec3& n);

// Mirror reflection of d about the unit shading normal n, whose changes along the surface for the hit's
// dp_du and dp_dv are dn_du and dn_dv: r = d - 2 (d . n) n, dr = dd - 2 ((d . n) dn + (dd . n + d . dn) n).
void reflect_differential(RayDifferential& differential, const Vec3& d, const Vec3& n, const Vec3& dn_du,
                          const Vec3& dn_dv);

// Refraction of d through the unit normal n facing the incident side (d . n < 0), eta = n_transmitted /
// n_incident as core/optics.h's refract: t = d / eta + (c_i / eta - c_t) n, c_i = -d . n, c_t its
// transmitted cosine; the derivative of each term. Nothing changes under total internal reflection
// (the caller reflects instead).
void refract_differential(RayDifferential& differential, const Vec3& d, const Vec3& n, const Vec3& dn_du,
                          const Vec3& dn_dv, float eta);

// The footprint's area, |dp_du x dp_dv| du dv, for a texel of du x dv.
inline float footprint_area(const RayDifferential& differential, float du, float dv) {
  return glm::length(glm::cross(differential.dp_du, differential.dp_dv)) * du * dv;
}

}  // namespace causticbench
