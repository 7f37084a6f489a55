// rt_photons' emission map (Yang & Ouyang 2021): per light sample, a light-space grid of texels over what
// the specular objects cover, each texel emitting photons toward them. A distant direction's grid lies on a
// plane across its beam (the bounding square of the objects' bounding disks seen from the light); a point's
// on the six faces of a unit cube around it (each texel a bundle of directions). Texels that cannot reach a
// specular object's bounding sphere are inactive: photons go only toward specular objects.
//
// A delta light (a parallel beam, a point) is one sample. An extended one is `light_samples` of them:
// directions drawn from a sun's disk, a Gaussian spot or an environment map by the light's own importance
// sampling, or points on a sphere light's surface, from a scrambled Sobol sequence redrawn every frame (so
// that frames are independent estimates of the blur, and temporal accumulation averages them). A sun's
// disk's and a sphere light's samples share one map (padded by the blur's reach), each photon taking one
// of them; an environment's or a Gaussian spot's directions are too far apart for one plane (nor are a
// wide disk's or sphere's), and each gets its own map carrying 1/K of the light: a plane of resolution /
// sqrt(K) a side, or a cube at the full resolution.
#pragma once

#include <cstdint>
#include <vector>

#include "core/light.h"
#include "core/ray_differential.h"
#include "core/scene.h"

namespace causticbench::rt_photons {

struct EmissionGrid {
  LightKind kind = LightKind::directional;  // directional (a plane across a beam) or point (a cube)
  size_t light = 0;    // the light's index in the frame's lights
  Color emitted{0.0f};  // directional: irradiance across the beam (W/m^2); point: intensity (W/sr)
  Vec3 origin{0.0f};    // point: where its photons leave
  int samples = 1;  // the light's samples: K maps (K per photon where the samples share this one)
  // A small sun's disk or sphere light whose samples share this map: each photon takes one of the light's
  // K directions of travel (directional) or emission points (point), with that sample's irradiance or
  // intensity (empty otherwise). Their beams overlap but for the blur, so the photons keep one map's
  // stratification and footprints; directional photons pass through their point on the plane `through`
  // beyond the map's own (that of the objects' middle), so that the blur does not move them there.
  std::vector<Vec3> sample_travel, sample_origin;
  std::vector<Color> sample_emitted;
  float through = 0.0f;
  // Of the light's maps, how many overlap this one's beam, so that a photon's footprint is that of their
  // photons together: all of a wide sun's disk's, a Gaussian spot's or a sphere light's (one lobe: their
  // caustics coincide but for the blur); one for an environment map's, whose directions spread so far that
  // each draws its caustic apart. Measured: the capability case's 0.02 sr sun with each direction's own
  // footprints lost its caustic's sharp edge (relMSE 0.52 against 0.02); the bunny under the forest map
  // with the map's total density lost detail (FLIP 0.195 against 0.151 at 256 directions,
  // yang2021_environment.yaml with full-resolution maps per direction).
  int overlapping = 1;
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

// Whether `light` is one sample: a parallel beam, or a point light of no radius.
bool is_delta_light(const LightFrame& light);

// The grids of `light` (index `light_index`) over `targets` (the specular objects' bounding spheres),
// `resolution` texels a side, each plane behind every object of the scene (`scene`): one for a delta light,
// `light_samples` for an extended one, drawn from `sample_seed` (none where there are no targets).
std::vector<EmissionGrid> emission_grids(const LightFrame& light, size_t light_index, const std::vector<BoundingSphere>& targets,
                                         const BoundingSphere& scene, int resolution, int light_samples, uint64_t sample_seed);

// The flux (luminance, W) a texel sends into the scene: E h^2 for a distant light, I times the texel's solid
// angle for a point light.
double texel_flux(const EmissionGrid& grid, size_t texel);

// A photon leaving texel `texel` at fractions (s, t) in [0, 1)^2 of it, taking the light's sample at
// fraction `pick` of them (where the map has samples): its ray, the power it carries when `share` of the
// texel is its own (1 / the texel's expected photons), and its ray differentials with respect to the
// texel's plane coordinates (u, v), so that a spacing of texel sqrt(share) gives its own patch of the beam.
void emit_photon(const EmissionGrid& grid, size_t texel, float s, float t, float pick, double share, Ray& ray, Color& power,
                 RayDifferential& differential);

}  // namespace causticbench::rt_photons
