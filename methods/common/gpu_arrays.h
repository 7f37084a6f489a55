// The G-buffer and images as the methods' Vulkan kernels and frame dumps take them: RGBA float32 per
// pixel, row-major (docs/gpu.md). One definition for pinhole, lpi and csl, so that their kernels and
// dumps agree on the receiver flag and the output layout.
#pragma once

#include <string>
#include <vector>

#include "core/gbuffer.h"
#include "core/image.h"

namespace causticbench {

// Positions with w = 1 at receivers and 0 elsewhere (the kernels return at once there, and
// receiver_dump_info reads the mask from it); normals with w = 0, which a method may fill with a
// per-pixel quantity of its own.
void fill_receiver_arrays(const GBuffer& gbuffer, std::vector<float>& positions, std::vector<float>& normals);

// A kernel's RGBA output as an RGB image, and back.
Image image_of_rgba(int width, int height, const std::vector<float>& rgba);
std::vector<float> rgba_of(const Image& image);

// DIR/BACKEND_irradiance.bin: the run's output, for gpu-compare.
void write_dump_irradiance(const std::string& folder, const std::string& backend, const Image& output);

}  // namespace causticbench
