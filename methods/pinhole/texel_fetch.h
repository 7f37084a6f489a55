// The fetch half of the unfiltered reflection kernel (pinhole.cpp): for the samples that face both ways
// and look into a lit block, the bilinear light-map radiance (LightCubeMap::lookup_texel's arithmetic)
// times the tabulated throughput (throughput.h) times the geometric weight, summed. With AVX2, eight
// samples at a time through gathers; the per-lane arithmetic is the scalar lookup's, only the order of
// the final sum differs (methods/pinhole/tests/test_pinhole.cpp bounds the difference). Under an environment map the
// texels are read from the shared-exponent copy (packed_texels.h), a third of the float map's size.
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/math.h"

namespace causticbench {

struct FetchBlock {
  const int* face;
  const float *texel_s, *texel_t, *weight, *cos_sample;
  const uint16_t* indices;  // the compacted samples of the block; null: every sample, compacted by the fetch
                            // by weight > 0 alone (a map lit everywhere)
  size_t count;             // how many of them (with null indices: the block's size, a multiple of 8, <= 256)
  const float* texels;      // LightCubeMap::texels(): RGB, face-major
  const uint32_t* packed;   // PackedTexels::texels() of the same map, or null: the float texels are read
  int32_t unit_bits;        // PackedTexels::unit_bits()
  int resolution;           // texels per face side
  const float* throughput;  // every ThroughputTable's values, RGB, kEntries + 1 per table, table after table
  const int32_t* table_of;  // the table of each sample of the block
  bool one_table;           // every sample has table 0 (table_of is not read)
};

// Whether this processor runs the vector fetch (AVX2), and whether CAUSTICBENCH_PINHOLE_SCALAR_FETCH is
// unset (set it to compare with the scalar fetch).
bool vector_fetch_enabled();

// Adds the contributions of the first multiple of eight of the block's samples to `sum`; returns how
// many it took (the caller fetches the rest one by one). Only where vector_fetch_enabled().
size_t fetch_sum_avx2(const FetchBlock& block, Color& sum);

}  // namespace causticbench
