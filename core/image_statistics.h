// Masked image statistics used inside the renderers (the reference's estimated error). The metrics module
// builds the full, documented metric set on top of the same definitions.
#pragma once

#include <cstdint>
#include <vector>

#include "core/image.h"

namespace causticbench {

// Mean over masked pixels of the per-channel mean of (a - b)^2 / (b^2 + epsilon), with
// epsilon = (0.1 * mean of b over the mask)^2: pbrt's relMSE with its epsilon made relative, so that
// the value does not depend on the scene's units and dark pixels do not dominate.
double relative_mse(const Image& test, const Image& reference, const std::vector<uint8_t>& mask);
// That epsilon for a reference whose masked mean is `mean` (the one definition, also used where an
// expected squared error stands in for (a - b)^2: the reference's own error estimate).
double relative_mse_epsilon(double mean);
double masked_mean(const Image& image, const std::vector<uint8_t>& mask);
// Sum over masked pixels of the channel mean (for energy comparisons).
double masked_sum(const Image& image, const std::vector<uint8_t>& mask);

}  // namespace causticbench
