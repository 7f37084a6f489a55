// The shared-exponent light map of the unfiltered vector fetch (declared in packed_texels.h).
#include "methods/pinhole/packed_texels.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace causticbench {

namespace {

constexpr int kLargestExponent = 31;  // 5 bits
constexpr double kLargestMantissa = PackedTexels::kMantissaMask;

// The smallest exponent e >= 0 at which `largest` rounds to a mantissa that fits, with unit 2^offset.
int exponent_for(double largest, int offset) {
  int e = std::max(0, static_cast<int>(std::ceil(std::log2(largest / kLargestMantissa))) - offset);
  while (e < kLargestExponent && std::nearbyint(std::ldexp(largest, -(e + offset))) > kLargestMantissa) ++e;
  return std::min(e, kLargestExponent);
}

}  // namespace

PackedTexels::PackedTexels(const std::vector<float>& rgb) {
  const double largest = rgb.empty() ? 0.0 : *std::max_element(rgb.begin(), rgb.end());
  // The offset puts the map's largest texel at the top exponent; 2^(e + offset) stays a normal float.
  int offset = 0;
  if (largest > 0.0) {
    offset = static_cast<int>(std::ceil(std::log2(largest / kLargestMantissa))) - kLargestExponent;
    while (std::nearbyint(std::ldexp(largest, -(kLargestExponent + offset))) > kLargestMantissa) ++offset;
    offset = std::clamp(offset, -126, 127 - kLargestExponent);
  }
  unit_ = std::ldexp(1.0f, offset);
  texels_.resize(rgb.size() / 3);
  for (size_t i = 0; i < texels_.size(); ++i) {
    const double r = rgb[3 * i], g = rgb[3 * i + 1], b = rgb[3 * i + 2];
    const double texel_largest = std::max({r, g, b});
    if (!(texel_largest > 0.0)) {
      texels_[i] = 0;
      continue;
    }
    const int e = exponent_for(texel_largest, offset);
    auto mantissa = [&](double value) {
      return static_cast<uint32_t>(std::min(kLargestMantissa, std::nearbyint(std::ldexp(value, -(e + offset)))));
    };
    texels_[i] = mantissa(r) | mantissa(g) << kMantissaBits | mantissa(b) << (2 * kMantissaBits) |
                 static_cast<uint32_t>(e) << kExponentShift;
    const Color decoded = decode(texels_[i]);
    const double error = std::max({std::abs(decoded.r - r), std::abs(decoded.g - g), std::abs(decoded.b - b)});
    max_relative_error_ =
        std::max(max_relative_error_, static_cast<float>(error / std::max(texel_largest, std::ldexp(largest, -kLargestExponent))));
  }
}

int32_t PackedTexels::unit_bits() const {
  int32_t bits;
  std::memcpy(&bits, &unit_, sizeof(bits));
  return bits;
}

Color PackedTexels::decode(uint32_t texel) const {
  const float scale = std::ldexp(unit_, static_cast<int>(texel >> kExponentShift));
  return Color(static_cast<float>(texel & kMantissaMask), static_cast<float>(texel >> kMantissaBits & kMantissaMask),
               static_cast<float>(texel >> (2 * kMantissaBits) & kMantissaMask)) *
         scale;
}

}  // namespace causticbench
