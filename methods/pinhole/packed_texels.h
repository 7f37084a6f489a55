// A compact copy of the light cube map for the unfiltered kernel's vector fetch (texel_fetch.cpp): every
// RGB texel in 32 bits, three 9-bit mantissas and a 5-bit exponent shared by the three channels
// (RGB9E5's layout), with an exponent offset per map so that the map's largest texel fits whatever its
// scale. Under an environment map every sample-pixel pair fetches; the float map (12 bytes a texel,
// 4.7 MB at 256^2 x 6) spilled out of the second-level cache and the fetch waited on memory. Packed, the
// map is a third of that and a bilinear lookup is four gathers instead of twelve.
//
// Precision: each channel is rounded to the nearest multiple of 2^(e + offset), where the texel's largest
// channel has a mantissa in [256, 511]: every channel is within 2^-9 (0.2 %) of the texel's largest
// channel (2^-10 where that mantissa is near 511). Texels dimmer than 2^-31 of the map's largest have
// e = 0 and lose bits: every channel of every texel is within max(2^-9 x its texel's largest channel,
// 2^-40 x the map's largest value).
#pragma once

#include <cstdint>
#include <vector>

#include "core/math.h"

namespace causticbench {

class PackedTexels {
 public:
  static constexpr int kMantissaBits = 9;
  static constexpr uint32_t kMantissaMask = (1u << kMantissaBits) - 1;
  static constexpr int kExponentShift = 3 * kMantissaBits;  // the top 5 bits

  PackedTexels() = default;
  // rgb: RGB floats, as LightCubeMap::texels() (non-negative, finite).
  explicit PackedTexels(const std::vector<float>& rgb);

  const std::vector<uint32_t>& texels() const { return texels_; }
  // The float value of mantissa 1 at exponent 0: 2^offset. A texel's channel is mantissa x 2^e x unit().
  float unit() const { return unit_; }
  // The float bits of unit(), for the vector decode (exponent field added to e << 23).
  int32_t unit_bits() const;
  Color decode(uint32_t texel) const;
  // The largest deviation of a decoded channel from the float map, relative to the larger of its texel's
  // largest channel and 2^-31 of the map's largest value (measured when packed; at most 2^-9).
  float max_relative_error() const { return max_relative_error_; }

 private:
  std::vector<uint32_t> texels_;
  float unit_ = 1.0f;
  float max_relative_error_ = 0.0f;
};

}  // namespace causticbench
