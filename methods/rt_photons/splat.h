// rt_photons' splatting (Yang & Ouyang 2021): each landed photon spread over its own footprint on the
// surface it hit, into the camera's caustic buffer. The footprint is an elliptical kernel from the photon's
// ray differentials (the parallelogram its patch of the beam spans there), a ray cone's disc, or a fixed
// radius, its axes clamped between min and max pixels once projected. A G-buffer point under it counts
// when it lies on the same surface (within a plane distance of a pixel's footprint and 25 degrees of the
// hit's normal: the depth test a GPU rasteriser would make); the kernel is normalised over the points that
// count, weighted by each one's surface area, so that the photon's flux is conserved exactly, whatever the
// receivers' edge or a depth discontinuity cuts off: irradiance is flux per surface area. Beyond the image's
// edge the surface is unseen but goes on: there the kernel is taken on the photon's plane, so that a photon
// at the edge puts inside only the share of its flux that lands inside.
//
// The pass is a GPU's: per photon (in parallel) the kernel, its pixel bounds and its normaliser; the
// photons binned by screen tile in photon order; per tile (in parallel) the deposits. A Vulkan compute or
// raster backend would take the landed photons as its input (README.md, "A GPU port").
#pragma once

#include <cstdint>
#include <vector>

#include "core/camera.h"
#include "core/gbuffer.h"
#include "core/image.h"

namespace causticbench::rt_photons {

enum class Footprint { ray_differentials, ray_cone, fixed };
Footprint footprint_kind(const std::string& name);  // std::invalid_argument for another name

// A photon where it landed: its flux, the surface's normal on its side, and the footprint's two axes on
// the surface (ray_differentials: the differentials times the photon's spacing; ray_cone: the cone's
// width along both; fixed: unused).
struct LandedPhoton {
  Vec3 position{0.0f};
  Vec3 normal{0.0f};
  Color power{0.0f};
  Vec3 axis_u{0.0f}, axis_v{0.0f};
  float cone_width = 0.0f;
  uint32_t texel = 0;  // the emission texel it left (its index in the frame's texel list)
};

struct SplatSettings {
  Footprint footprint = Footprint::ray_differentials;
  float min_pixels = 1.0f;    // the kernel's axes, in pixels at the hit
  float max_pixels = 32.0f;
  float fixed_pixels = 4.0f;  // footprint: fixed
};

struct SplatCounts {
  uint64_t splatted = 0;        // photons that reached at least one G-buffer point
  uint64_t hidden = 0;          // photons on a surface no pixel sees (occluded or outside the image)
  uint64_t pixels = 0;          // (photon, pixel) deposits
  uint64_t clamped_small = 0;   // photons whose kernel was widened to min_pixels
  uint64_t clamped_large = 0;   // ... narrowed to max_pixels
  double splatted_flux = 0.0;   // luminance, W
  double hidden_flux = 0.0;
};

// E_c per pixel (RGB) from `photons` (each carries its own flux, W). With `footprint_pixels`, per photon
// its kernel's radius in pixels before the clamps (the geometric mean of its axes; 0 for a photon no
// pixel sees): what adaptive emission steers.
Image splat_photons(const std::vector<LandedPhoton>& photons, const CameraFrame& camera, const GBuffer& gbuffer,
                    const SplatSettings& settings, SplatCounts& counts, std::vector<float>* footprint_pixels = nullptr);

}  // namespace causticbench::rt_photons
