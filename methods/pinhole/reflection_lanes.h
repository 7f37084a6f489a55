// The vectorised geometric parts of pinhole's CPU kernel (pinhole.cpp): per receiver point and a block
// of reflector samples, eight at a time with AVX2 (four with SSE2 where AVX2 is missing, chosen at
// run time): the unfiltered reflection's cube-map texel and weight, and the filtered reflection's
// conservative skip of footprints that reach no light (CubeFilter::may_reach_light's bound).
#pragma once

#include <cstddef>

#include "core/math.h"

namespace causticbench {

struct ReflectionBlock {
  size_t count;  // a multiple of 8 (the arrays are padded)
  const float *px, *py, *pz, *nx, *ny, *nz, *two_sided;
  Vec3 x, receiver_normal;
  float epsilon, area, resolution;
  float occupancy_blocks;  // LightCubeMap::occupancy_blocks(): blocks per face side
  bool attenuation;
  int* face;
  int* block;  // LightCubeMap::occupancy_index of the bilinear lookup's first texel
  float *texel_s, *texel_t, *weight, *cos_sample;
};

void reflection_block(const ReflectionBlock& block);

struct FilteredSkipBlock {
  size_t count;  // a multiple of 8 (the arrays are padded)
  const float *px, *py, *pz, *nx, *ny, *nz;
  const float* moved[12];  // p + r u (xyz), p + r v (xyz), their normals (xyz, xyz); structure of arrays
  Vec3 x;
  const float* cones;  // CubeFilter::lit_cone_data()
  size_t cone_count;
  float support_per_texel, half_resolution;
  bool anisotropic;
  float* keep;  // 1 where the exact lookup may be non-zero, 0 where it is 0 for sure
};

void filtered_skip(const FilteredSkipBlock& block);

}  // namespace causticbench
