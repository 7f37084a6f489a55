// What a scene requires (issue 52): the share of the reference's caustic light in each light-path class
// (core/path_classes.h), in view (the photons the footprint tally credits to a receiver pixel, each
// weighted as the image weights it, by its pixel's pixels per unit area, and by its channels' mean, so that
// a share is a share of the image's E_c summed as an energy ratio sums it) and everywhere (every photon's
// flux, luminance, deposited on a receiver, in view or not), with the sampling error of each share
// from the spread of the replicates (the passes of stratified emission, independent of each other).
// Stored with the reference's record ("path_classes", methods/reference/README.md, "What a scene requires").
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/path_classes.h"
#include "core/photon_tracer.h"

namespace causticbench {

class PathClassTally {
 public:
  // One replicate's flux per photon emitted (W, luminance), per class and in all.
  struct Sums {
    std::array<double, kPathInteractions> interaction{};
    std::array<double, kPathLights> light{};
    std::array<double, kPathReceivers> receiver{};
    // (interaction * kPathLights + light) * kPathReceivers + receiver
    std::array<double, kPathInteractions * kPathLights * kPathReceivers> joint{};
    double total = 0.0;
    double blocked = 0.0;  // the flux occluders took (CausticPhotonTracer::Blocked), not in `total`
  };
  // Where the footprint tally sees each photon: the measurement point it is credited to (-1: not in
  // view) and its pixel's pixels per unit area (FootprintTally::credit's weight).
  struct InView {
    const std::vector<int32_t>& targets;
    const std::vector<double>& weights;
    bool seen(size_t i) const { return i < targets.size() && targets[i] >= 0; }
    double weight(size_t i) const { return i < weights.size() ? weights[i] : 0.0; }
  };
  // One replicate of `emitted` photons: `classes[i]` is photon i's PathClass::packed; `seen` where the
  // arriving photons are seen, `blocked_seen` the blocked paths' photons.
  void add_replicate(const std::vector<Photon>& photons, const std::vector<uint8_t>& classes, InView seen,
                     const CausticPhotonTracer::Blocked& blocked, InView blocked_seen, uint64_t emitted);
  // {"definition", "in_view": {...}, "everywhere": {...}}; "in_view" holds "pixel_sum" (E_c summed over
  // the receiver pixels, the mean of its channels: the image's sum as an energy ratio takes it), "everywhere" "flux" (W,
  // luminance, over the photons emitted); each "replicates", and per interaction, light and receiver class its "share",
  // "standard_error" (null with fewer than two replicates) and the "capability" a method needs for it
  // ("" for none); "joint" the same per triple "interaction/light/receiver" (its "capabilities", those
  // that are not ""), from which a method's model share is summed; "occlusion": the blocked flux's "share",
  // blocked / (arrived + blocked), with its standard error (arrived counts the light on an occluder too, so
  // a receiver that blocks the light behind it adds to both),
  // and "excess", blocked / arrived: how much more than the reference a method without occlusion may put out.
  nlohmann::json to_json() const;

 private:
  std::vector<Sums> in_view_, everywhere_;  // per replicate
};

}  // namespace causticbench
