// The image lookups of a tile's rays eight at a time (csl's CPU backend, `lanes: vector`): after
// tile_rays (evaluation_lanes.h) has found each point's candidate rays and their light plane points, the
// bilinear lookups of one candidate for all eight points are AVX2 gathers from a stored one-channel
// image (uint16 or float32), and each ray's value times its correction and cosine is added per point in
// double, as tile_value adds it one ray at a time. Every lane runs IntensityImage::lookup's and
// tile_value's operations in their order and precision (no fused multiply-add: the AVX2 target has
// none), so the values are the same bit for bit (tested). Lanes whose bilinear square leaves the
// image's texels (its border) take the scalar lookup; points near the axis take the scalar evaluation,
// as in tile_value. Three-channel images, blended (interpolated) images and processors without AVX2
// keep tile_value.
#pragma once

#include "methods/csl/evaluation_lanes.h"

namespace causticbench::csl {

// Whether tile_lookups can read `image` on this processor: one channel and AVX2.
bool tile_lookups_apply(const IntensityImage& image);

// Adds to value[i], i < count, what the candidate rays of point i in `rays` read from `image` (one
// channel, tile_lookups_apply), times their correction and cosine: tile_value's sum without its
// near-axis points, which the caller evaluates (rays.near_axis). `value` has kTilePoints entries.
void tile_lookups(const IntensityImage& image, const TileRays& rays, size_t count, float* value);

}  // namespace causticbench::csl
