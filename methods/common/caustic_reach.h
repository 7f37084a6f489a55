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
  };
  std::vector<Hit> hits;  // sorted by distance
  double total_flux = 0.0;
  uint64_t photons = 0;   // probe photons emitted

  // The smallest distance within which `fraction` of the hits' flux lies (0 when there is none).
  double radius_holding(double fraction) const;
  // The fraction of the hits' flux beyond `radius` bounding radii (0 when there is none).
  double fraction_beyond(double radius) const;
};

// Traces `photons` probe photons (indices from 0, `seed`) from `frame`'s lights towards object `object`'s
// bounding sphere through the whole scene of `tracer`; each first receiver hit is mapped into the
// object's build space by `map` (this frame's) and measured from `build_bounds`' centre in its radii.
// The same for any thread count.
CausticReach probe_caustic_reach(const SceneFrame& frame, const Tracer& tracer, int object, const BuildSpaceMap& map,
                                 const BoundingSphere& build_bounds, uint64_t photons, uint64_t seed);

}  // namespace causticbench
