// Whether a reference frame has any caustic in view: the one rule behind the check that stops an
// experiment whose reference measures nothing (experiments/runner.cpp) and the warning of
// `causticbench render --method reference` (docs/metrics.md, "Empty references").
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/image.h"

namespace causticbench {

// E_c counts as absent when its sum over the receivers is at most this fraction of the direct
// irradiance's sum over them. A real caustic covering a single pixel of a 1000 x 1000 view at the
// brightness of the direct light is 1e-6 of it; reference noise in an empty view is exactly 0.
constexpr double kEmptyCausticFraction = 1e-6;

// What to look at when a reference has no caustic in view.
extern const char* const kEmptyCausticHint;

struct CausticPresence {
  size_t receiver_pixels = 0;
  double caustic_sum = 0.0;  // sum over the receiver pixels of E_c's channel mean, W/m^2
  double direct_sum = 0.0;   // the same for the direct irradiance

  // No receiver pixel, or caustic_sum <= kEmptyCausticFraction * direct_sum (so also caustic_sum = 0).
  bool empty() const;
  // The measured sums and the rule, as one clause for messages.
  std::string describe() const;
};

// `caustic` and `direct` have the receivers' size; `receivers` holds one byte per pixel, non-zero on a
// receiver (GBuffer::receiver).
CausticPresence measure_caustic_presence(const Image& caustic, const Image& direct,
                                         const std::vector<uint8_t>& receivers);

}  // namespace causticbench
