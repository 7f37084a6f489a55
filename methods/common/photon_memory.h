// What a traced batch of caustic photons costs in memory, for the methods' knob_memory terms
// (photon_map's `photons`, the reference's `photons_per_pass`).
#pragma once

#include <cstdint>

#include "methods/method.h"

namespace causticbench {

// CausticPhotonTracer::trace holds every deposited photon twice at its peak (one vector per block of
// paths, then the merged vector they are copied into): 2 x sizeof(Photon) = 96 bytes, rounded up to 100.
// Measured (issue 30): 96 to 97 bytes per deposited photon on the glass sphere, the ring and the prism.
constexpr double kBytesPerTracedPhoton = 100.0;

// An upper bound on the photons deposited per photon emitted. A path deposits once on each diffuse
// surface it meets after a specular bounce and ends there unless that surface is a diffuse_mirror, so
// without one the bound is 1 (measured: 0.29 on the bunny to 0.9 on the glass sphere). With one a path
// may deposit many times: a pilot of 16384 photons is traced and its rate taken with a margin of 1.25.
double deposits_per_photon_bound(const PrepareContext& context, uint64_t seed, int max_bounces);

}  // namespace causticbench
