// lpi's state as the Vulkan backend and `--dump-frame` take it (methods/lpi/frame_data.h): the build's
// values and shell tables, the frame's maps and light reads, the receivers. Which combinations the
// kernel evaluates is decided here, before any work starts.
#pragma once

#include <vector>

#include "core/gbuffer.h"
#include "methods/lpi/frame_data.h"
#include "methods/lpi/lookup.h"
#include "methods/lpi/precompute.h"

namespace causticbench::lpi {

// Throws InputError, saying what the kernel supports, when `settings` is not a combination it
// evaluates (multires and sh storage); `what` names what needs the kernel.
void check_vulkan_supports(const VolumeSettings& settings, const std::string& what = "backend vulkan");

// The build's part: values, scales, shell tables, and each object's record words that do not
// change per frame (layout, offsets). Replaces everything else in `frame` but the receivers.
void fill_volume_data(const VolumeSettings& settings, const std::vector<ObjectVolumes>& objects, LpiFrameData& frame);
// The frame's part: each object's build-space map and its lights' reads, and the outside mode.
void fill_frame_lights(const std::vector<ObjectFrame>& views, Outside outside, LpiFrameData& frame);
// The receivers: world-space positions (w: 1 for a receiver) and normals.
void fill_receivers(const GBuffer& gbuffer, LpiFrameData& frame);

}  // namespace causticbench::lpi
