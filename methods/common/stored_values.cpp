#include "methods/common/stored_values.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace causticbench {

Precision parse_precision(const std::string& name) {
  if (name == "uint8") return Precision::uint8;
  if (name == "float16") return Precision::float16;
  if (name == "float32") return Precision::float32;
  throw std::invalid_argument("unknown precision '" + name + "'");
}

std::string precision_name(Precision precision) {
  switch (precision) {
    case Precision::uint8: return "uint8";
    case Precision::float16: return "float16";
    case Precision::float32: return "float32";
  }
  return "?";
}

size_t precision_bytes(Precision precision) {
  switch (precision) {
    case Precision::uint8: return 1;
    case Precision::float16: return 2;
    case Precision::float32: return 4;
  }
  return 4;
}

uint16_t float_to_half(float value) {
  uint32_t bits;
  std::memcpy(&bits, &value, sizeof(bits));
  const uint32_t sign = (bits >> 16) & 0x8000u;
  const int exponent = static_cast<int>((bits >> 23) & 0xffu) - 127 + 15;
  uint32_t mantissa = bits & 0x7fffffu;
  if (((bits >> 23) & 0xffu) == 0xffu) return static_cast<uint16_t>(sign | 0x7c00u | (mantissa ? 0x200u : 0u));
  if (exponent >= 31) return static_cast<uint16_t>(sign | 0x7c00u);
  if (exponent <= 0) {
    if (exponent < -10) return static_cast<uint16_t>(sign);
    mantissa |= 0x800000u;
    const int shift = 14 - exponent;
    uint32_t half_mantissa = mantissa >> shift;
    const uint32_t remainder = mantissa & ((1u << shift) - 1u), halfway = 1u << (shift - 1);
    if (remainder > halfway || (remainder == halfway && (half_mantissa & 1u))) ++half_mantissa;
    return static_cast<uint16_t>(sign | half_mantissa);
  }
  uint32_t half = sign | (static_cast<uint32_t>(exponent) << 10) | (mantissa >> 13);
  const uint32_t remainder = mantissa & 0x1fffu;
  // Carry into the exponent is what rounding up the largest mantissa should do.
  if (remainder > 0x1000u || (remainder == 0x1000u && (half & 1u))) ++half;
  return static_cast<uint16_t>(half);
}

StoredValues StoredValues::encode(Precision precision, int channels, bool signed_channels, size_t points,
                                  const std::vector<float>& values) {
  const size_t block = points * static_cast<size_t>(channels);
  if (block == 0 || values.size() % block != 0) {
    throw std::logic_error(fmt::format("StoredValues::encode: {} values are not whole blocks of {}", values.size(), block));
  }
  StoredValues stored = encode(precision, channels, signed_channels, std::vector<size_t>(values.size() / block, points), values);
  stored.block_first_.clear();
  stored.points_ = points;
  return stored;
}

StoredValues StoredValues::encode(Precision precision, int channels, bool signed_channels,
                                  const std::vector<size_t>& block_points, const std::vector<float>& values) {
  StoredValues stored;
  stored.precision_ = precision;
  stored.channels_ = channels;
  stored.signed_ = signed_channels;
  stored.block_first_.assign(1, 0);
  for (size_t points : block_points) stored.block_first_.push_back(stored.block_first_.back() + points);
  stored.points_ = stored.block_first_.back();
  if (values.size() != stored.points_ * static_cast<size_t>(channels)) {
    throw std::logic_error(fmt::format("StoredValues::encode: {} values for {} points of {} channels", values.size(),
                                       stored.points_, channels));
  }
  const size_t light_samples = block_points.size();
  stored.scales_.assign(light_samples, 1.0f);
  stored.bytes_.resize(values.size() * precision_bytes(precision));
  for (size_t sample = 0; sample < light_samples; ++sample) {
    const size_t first = stored.block_first_[sample] * static_cast<size_t>(channels);
    const size_t block = block_points[sample] * static_cast<size_t>(channels);
    const float* input = values.data() + first;
    switch (precision) {
      case Precision::float32:
        if (block > 0) std::memcpy(stored.bytes_.data() + first * 4, input, block * 4);
        break;
      case Precision::float16: {
        uint16_t* output = reinterpret_cast<uint16_t*>(stored.bytes_.data()) + first;
        for (size_t i = 0; i < block; ++i) {
          output[i] = float_to_half(input[i]);
          if (std::isinf(half_to_float(output[i]))) {
            throw std::runtime_error(fmt::format("value {} exceeds float16's range; use precision: float32", input[i]));
          }
        }
        break;
      }
      case Precision::uint8: {
        float largest = 0.0f;
        for (size_t i = 0; i < block; ++i) largest = std::max(largest, std::fabs(input[i]));
        const float levels = signed_channels ? 127.0f : 255.0f;
        const float step = largest > 0.0f ? largest / levels : 1.0f;
        stored.scales_[sample] = step;
        uint8_t* output = stored.bytes_.data() + first;
        for (size_t i = 0; i < block; ++i) {
          float level = std::round(input[i] / step);
          level = std::clamp(level, signed_channels ? -127.0f : 0.0f, levels);
          if (signed_channels) {
            int8_t signed_level = static_cast<int8_t>(level);
            std::memcpy(output + i, &signed_level, 1);
          } else {
            output[i] = static_cast<uint8_t>(level);
          }
        }
        break;
      }
    }
  }
  return stored;
}

std::vector<float> StoredValues::decode(size_t light_sample) const {
  const size_t points = block_points(light_sample);
  std::vector<float> values(points * channels_, 0.0f);
  for (size_t point = 0; point < points; ++point) add(light_sample, point, 1.0f, values.data() + point * channels_);
  return values;
}

StoredValues StoredValues::from_raw(Precision precision, int channels, bool signed_channels, size_t points,
                                    std::vector<uint8_t> bytes, std::vector<float> scales) {
  const size_t blocks = scales.size();
  StoredValues stored =
      from_raw(precision, channels, signed_channels, std::vector<size_t>(blocks, points), std::move(bytes), std::move(scales));
  stored.block_first_.clear();
  stored.points_ = points;
  return stored;
}

StoredValues StoredValues::from_raw(Precision precision, int channels, bool signed_channels,
                                    const std::vector<size_t>& block_points, std::vector<uint8_t> bytes,
                                    std::vector<float> scales) {
  StoredValues stored;
  stored.precision_ = precision;
  stored.channels_ = channels;
  stored.signed_ = signed_channels;
  stored.block_first_.assign(1, 0);
  for (size_t points : block_points) stored.block_first_.push_back(stored.block_first_.back() + points);
  stored.points_ = stored.block_first_.back();
  stored.bytes_ = std::move(bytes);
  stored.scales_ = std::move(scales);
  const size_t expected = stored.points_ * static_cast<size_t>(channels) * precision_bytes(precision);
  if (stored.scales_.size() != block_points.size() || stored.bytes_.size() != expected) {
    throw std::runtime_error(fmt::format("stored values: {} bytes and {} scales for {} light samples of {} bytes in all",
                                         stored.bytes_.size(), stored.scales_.size(), block_points.size(), expected));
  }
  return stored;
}

}  // namespace causticbench
