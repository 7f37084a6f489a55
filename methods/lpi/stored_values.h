// The sampled caustic of one object, for every light sample, in the precision the build asked for
// (Wyman 2003 stored "colors of three bytes each"). One block per light sample; within a block,
// `channels` values per sample point (cell centre or shell vertex), point after point. Values are
// decoded where they are read, so memory_bytes() is what rendering really touches.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace causticbench::lpi {

enum class Precision { uint8, float16, float32 };
Precision parse_precision(const std::string& name);
std::string precision_name(Precision precision);
size_t precision_bytes(Precision precision);

// IEEE half precision, round to nearest even; values beyond its range become infinities, which the
// build refuses (see StoredValues::encode).
uint16_t float_to_half(float value);
float half_to_float(uint16_t half);

class StoredValues {
 public:
  StoredValues() = default;
  // `values`: light_samples * points * channels floats. uint8 stores each light sample's channels
  // linearly from 0 to that block's largest magnitude (signed channels, as vector irradiance has,
  // as -127 .. 127); the scale per block is kept in float.
  static StoredValues encode(Precision precision, int channels, bool signed_channels, size_t points,
                             const std::vector<float>& values);

  Precision precision() const { return precision_; }
  int channels() const { return channels_; }
  size_t points() const { return points_; }
  size_t light_samples() const { return scales_.size(); }
  size_t memory_bytes() const { return bytes_.size() + scales_.size() * sizeof(float); }
  size_t bytes_per_light_sample() const { return points_ * channels_ * precision_bytes(precision_); }

  // Adds weight * value of `point` of `light_sample` to out[0 .. channels).
  inline void add(size_t light_sample, size_t point, float weight, float* out) const;
  // Every value of one light sample, decoded (tests, the SH projection).
  std::vector<float> decode(size_t light_sample) const;

  // Raw form for the build cache.
  const std::vector<uint8_t>& bytes() const { return bytes_; }
  const std::vector<float>& scales() const { return scales_; }
  static StoredValues from_raw(Precision precision, int channels, bool signed_channels, size_t points,
                               std::vector<uint8_t> bytes, std::vector<float> scales);
  bool signed_channels() const { return signed_; }

 private:
  Precision precision_ = Precision::float32;
  int channels_ = 0;
  bool signed_ = false;
  size_t points_ = 0;
  std::vector<uint8_t> bytes_;
  std::vector<float> scales_;  // per light sample: the uint8 step; 1 otherwise
};

inline void StoredValues::add(size_t light_sample, size_t point, float weight, float* out) const {
  const size_t first = (light_sample * points_ + point) * static_cast<size_t>(channels_);
  switch (precision_) {
    case Precision::float32: {
      const float* values = reinterpret_cast<const float*>(bytes_.data()) + first;
      for (int c = 0; c < channels_; ++c) out[c] += weight * values[c];
      break;
    }
    case Precision::float16: {
      const uint16_t* values = reinterpret_cast<const uint16_t*>(bytes_.data()) + first;
      for (int c = 0; c < channels_; ++c) out[c] += weight * half_to_float(values[c]);
      break;
    }
    case Precision::uint8: {
      const float scaled = weight * scales_[light_sample];
      if (signed_) {
        const int8_t* values = reinterpret_cast<const int8_t*>(bytes_.data()) + first;
        for (int c = 0; c < channels_; ++c) out[c] += scaled * static_cast<float>(values[c]);
      } else {
        const uint8_t* values = bytes_.data() + first;
        for (int c = 0; c < channels_; ++c) out[c] += scaled * static_cast<float>(values[c]);
      }
      break;
    }
  }
}

inline float half_to_float(uint16_t half) {
  const uint32_t sign = static_cast<uint32_t>(half & 0x8000u) << 16;
  uint32_t exponent = (half >> 10) & 0x1fu;
  uint32_t mantissa = half & 0x3ffu;
  uint32_t bits;
  if (exponent == 0) {
    if (mantissa == 0) {
      bits = sign;
    } else {  // subnormal: normalise
      int shift = 0;
      while (!(mantissa & 0x400u)) {
        mantissa <<= 1;
        ++shift;
      }
      mantissa &= 0x3ffu;
      bits = sign | (static_cast<uint32_t>(127 - 15 - shift + 1) << 23) | (mantissa << 13);
    }
  } else if (exponent == 31) {
    bits = sign | 0x7f800000u | (mantissa << 13);
  } else {
    bits = sign | ((exponent + 127 - 15) << 23) | (mantissa << 13);
  }
  float value;
  std::memcpy(&value, &bits, sizeof(value));
  return value;
}

}  // namespace causticbench::lpi
