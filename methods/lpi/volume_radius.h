// lpi's sampled ball: methods/common/ball_radius.h, with the cells its storage puts across the ball.
// Decisions and their reasons: methods/lpi/README.md, "The sampled ball".
#pragma once

#include "methods/common/ball_radius.h"
#include "methods/lpi/precompute.h"

namespace causticbench::lpi {

using VolumeRadius = BallRadius;

// The largest ball auto chooses at these settings (ball_radius_cap of the cells or shells across it).
double volume_radius_cap(const VolumeSettings& settings);

// The ball for `object`: the number set, or with auto (settings.volume_radius == 0) what the probes need.
VolumeRadius choose_volume_radius(const PrepareContext& context, int object, const BoundingSphere& build_bounds,
                                  const VolumeSettings& settings);

}  // namespace causticbench::lpi
