// Does a device's cube-map sampler honour textureGrad's explicit gradients? Filtered GPU lookups (the
// pinhole method's `filtering`) are only meaningful if it does, and not every driver's anisotropic
// path does: Mesa 22.3's lavapipe takes its level of detail from neighbouring invocations instead.
#pragma once

#include <string>

#include "gpu/vulkan_context.h"

namespace causticbench::gpu {

struct CubeFilterCheck {
  bool anisotropic = false;
  // Mean |L - 1| over random directions on a map whose level 0 is a 0/2 checkerboard and whose other
  // levels are 1: about 0.25 for a footprint far below a texel (bilinear level 0), about 0 for a
  // footprint of many texels (a coarse level). Queries are shuffled so that neighbouring invocations
  // look in unrelated directions: a sampler that used implicit derivatives would see huge ones.
  double deviation_small_footprint = 0.0;
  double deviation_large_footprint = 0.0;
  bool honours_gradients = false;
  std::string summary() const;
};

CubeFilterCheck check_cube_filtering(Context& context, bool anisotropic);
// The same, run once per device name and mode in this process (the answer depends on nothing else).
CubeFilterCheck cached_cube_filter_check(Context& context, bool anisotropic);

}  // namespace causticbench::gpu
