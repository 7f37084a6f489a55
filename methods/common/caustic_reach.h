// Where an object's caustic first meets a receiver: the measurement behind a sampled volume's
// scene-derived size and its lost flux (issue 32). Probe photons leave the frame's own lights aimed at
// the object alone, are traced through the whole scene (every receiver, every other object), and each
// path's first deposit on a receiver is kept with its flux, as a distance from the centre of the
// object's build-space ball. lpi uses it for `volume_radius: auto` and for the flux outside its ball;
// PRT's transfer volume will do the same.
#pragma once

#include <cstdint>
#include <vector>

#include "core/scene.h"
#include "core/tracer.h"
#include "methods/common/build_space.h"

namespace causticbench {

struct CausticReach {
  // Per probe path that reached a receiver: its first receiver hit's distance from the ball's centre in
  // the object's bounding radii, and the flux it carries there (luminance, W per photon emitted).
  struct Hit {
    double distance = 0.0;
    double flux = 0.0;
    // What lpi's paper orientation (Wyman 2003, Section 3.2) renders of this photon's irradiance, as a
    // share of it: paper_orientation_share below.
    double paper_share = 1.0;
  };
  std::vector<Hit> hits;  // sorted by distance
  double total_flux = 0.0;
  uint64_t photons = 0;   // probe photons emitted

  // The smallest distance within which `fraction` of the hits' flux lies (0 when there is none).
  double radius_holding(double fraction) const;
  // The fraction of the hits' flux beyond `radius` bounding radii (0 when there is none).
  double fraction_beyond(double radius) const;
  // Of the hits within `radius` bounding radii, the flux the paper orientation renders: the sum of
  // flux x paper_share (0 when there is none).
  double paper_flux_within(double radius) const;
};

// lpi's paper orientation stores, per point P of the volume, the irradiance on a surface facing the
// object's centre C (each track weighted by max(0, d . u), u = (P - C) / |P - C|, d its direction of
// travel) and gives a receiver of normal n that value times max(0, -n . u). A photon that lands on the
// receiver travelling along d brings it irradiance in proportion to its flux; the volume holds its
// fluence, that irradiance over |n . d|. So the paper orientation renders of it the share
//   max(0, d . u) max(0, -n . u) / |n . d|,
// 1 where the light falls along u onto a receiver facing the centre (a floor under a ball), near 0 where
// the receiver turns away from the centre (the floor inside a ring, whose centre is beside it), above 1
// for light that grazes a receiver facing the centre. |n . d| is held at least kGrazingCosine: the
// share's mean over landing photons is finite (they land in proportion to |n . d|), a single grazing
// probe's is not. Vectors in one space, n the receiver's normal on the side the light arrives from.
inline constexpr double kGrazingCosine = 0.01;
double paper_orientation_share(const Vec3& travel, const Vec3& normal, const Vec3& from_center);

// Traces `photons` probe photons (indices from 0, `seed`) from `frame`'s lights towards object `object`'s
// bounding sphere through the whole scene of `tracer`; each first receiver hit is mapped into the
// object's build space by `map` (this frame's) and measured from `build_bounds`' centre in its radii,
// with its paper_orientation_share there.
// The same for any thread count.
CausticReach probe_caustic_reach(const SceneFrame& frame, const Tracer& tracer, int object, const BuildSpaceMap& map,
                                 const BoundingSphere& build_bounds, uint64_t photons, uint64_t seed);

}  // namespace causticbench
