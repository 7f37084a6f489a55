// rt_photons' emission map (Yang & Ouyang 2021): per light, a light-space grid of texels over what the
// specular objects cover, each texel emitting photons toward them. A directional light's grid lies on a
// plane across its beam (the bounding square of the objects' bounding disks seen from the light); a point
// light's on the six faces of a unit cube around it (each texel a bundle of directions). Texels that cannot
// reach a specular object's bounding sphere are inactive: photons go only toward specular objects.
#pragma once

#include <cstdint>
#include <vector>

#include "core/light.h"
#include "core/ray_differential.h"
#include "core/scene.h"

namespace causticbench::rt_photons {

struct EmissionGrid {
  LightKind kind = LightKind::directional;
  const LightFrame* light = nullptr;
  int resolution = 0;  // texels a side of a face
  int faces = 1;       // 1 (a plane across a distant light's beam) or 6 (a point light's cube)
  float texel = 0.0f;  // a texel's side, in plane units (directional: scene units; point: on the unit cube)
  // Per face: the corner of texel (0, 0) and the unit axes along which texels are laid out; for a point
  // light the face's centre direction (its axis) too. A point on a face is corner + u axis_u + v axis_v.
  std::vector<Vec3> corner, axis_u, axis_v;
  Vec3 travel{0.0f};  // directional: the beam's direction of travel
  std::vector<uint8_t> active;  // faces x resolution^2
  size_t texel_count() const { return active.size(); }
};

// The grid of `light` over `targets` (the specular objects' bounding spheres), `resolution` texels a side,
// its plane behind every object of the scene (`scene`). Environment lights have none (empty grid).
EmissionGrid emission_grid(const LightFrame& light, const std::vector<BoundingSphere>& targets,
                           const BoundingSphere& scene, int resolution);

// The flux (luminance, W) a texel sends into the scene: E h^2 for a distant light, I times the texel's solid
// angle for a point light.
double texel_flux(const EmissionGrid& grid, size_t texel);

// A photon leaving texel `texel` at fractions (s, t) in [0, 1)^2 of it: its ray, the power it carries
// when `share` of the texel is its own (1 / the texel's expected photons), and its ray differentials with
// respect to the texel's plane coordinates (u, v), so that a spacing of texel sqrt(share) gives its own
// patch of the beam.
void emit_photon(const EmissionGrid& grid, size_t texel, float s, float t, double share, Ray& ray, Color& power,
                 RayDifferential& differential);

}  // namespace causticbench::rt_photons
