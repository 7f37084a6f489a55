// Photon tracks of one distant light through one object, summed into per-point accumulators: what the
// volume estimators of lpi (Wyman 2003, a light sample's irradiance volume) and PRT (Sloan 2002, a source
// direction's transfer) precompute. Every segment after a photon's first specular bounce is handed to a
// deposit function with the sums of the photon's chunk; chunks are summed in chunk order a wave at a
// time, so the sums are the same for any thread count, and memory holds eight chunks' accumulators
// rather than one per photon block.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "core/photon_tracer.h"

namespace causticbench {

class PhotonTrackSums {
 public:
  // Accumulators of `values` floats each.
  explicit PhotonTrackSums(size_t values);
  size_t values() const { return values_; }
  // Traces photons [first_index, first_index + photons) of `tracer` (its lights and targets), calls
  // deposit(segment, sums) for each of their segments after the first specular bounce, and returns the
  // sums over all photons (double, before any normalisation); the tracer's statistics add to `stats`.
  // The sums are this object's own buffer, valid until the next call: the caller normalises them in
  // place rather than copying them (a copy is 8 bytes a value, a whole grid's worth at the build's peak).
  std::vector<double>& accumulate(const CausticPhotonTracer& tracer, uint64_t first_index, uint64_t photons,
                                  const std::function<void(const PathSegment&, float*)>& deposit,
                                  PhotonStats& stats);

 private:
  size_t values_;
  std::vector<std::vector<float>> chunk_sums_;
  std::vector<PhotonStats> chunk_stats_;
  std::vector<double> total_;
};

}  // namespace causticbench
