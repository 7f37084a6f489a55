// What a scene requires (issue 52): the share of the reference's caustic flux in each light-path class
// (core/path_classes.h), in view (the photons the footprint tally credits to a receiver pixel) and
// everywhere (every photon deposited on a receiver, in view or not), with the sampling error of each share
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
  // One replicate of `emitted` photons: `classes[i]` is photon i's PathClass::packed, `targets[i]` the
  // measurement point the footprint tally credited it to (-1: not in view); the same for the blocked paths.
  void add_replicate(const std::vector<Photon>& photons, const std::vector<uint8_t>& classes,
                     const std::vector<int32_t>& targets, const CausticPhotonTracer::Blocked& blocked,
                     const std::vector<int32_t>& blocked_targets, uint64_t emitted);
  // {"definition", "in_view": {...}, "everywhere": {...}}; each holds "flux" (W, luminance, over the
  // photons emitted), "replicates", and per interaction, light and receiver class its "share",
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
