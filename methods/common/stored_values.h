// The sampled caustic of one object, for every light sample, in the precision the build asked for
// (Wyman 2003 stored "colors of three bytes each"). One block per light sample; within a block,
// `channels` values per sample point (cell centre or shell vertex), point after point. Blocks hold
// the same points, except where each light sample has a layout of its own (multires, a tree per
// light sample): then each block its own count, one after the other. Values are
// decoded where they are read, so memory_bytes() is what rendering really touches.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

namespace causticbench {

enum class Precision { uint8, float16, float32 };
Precision parse_precision(const std::string& name);
std::string precision_name(Precision precision);
size_t precision_bytes(Precision precision);

// IEEE half precision, round to nearest even; values beyond its range become infinities, which the
// build refuses (see StoredValues::encode).
uint16_t float_to_half(float value);
inline float half_to_float(uint16_t half);

struct SampleBlock;

class StoredValues {
 public:
  StoredValues() = default;
  // `values`: light_samples * points * channels floats. uint8 stores each light sample's channels
  // linearly from 0 to that block's largest magnitude (signed channels, as vector irradiance has,
  // as -127 .. 127); the scale per block is kept in float.
  static StoredValues encode(Precision precision, int channels, bool signed_channels, size_t points,
                             const std::vector<float>& values);
  // Blocks of their own sizes: `block_points[b]` points in block b, the blocks one after the other.
  static StoredValues encode(Precision precision, int channels, bool signed_channels,
                             const std::vector<size_t>& block_points, const std::vector<float>& values);

  Precision precision() const { return precision_; }
  int channels() const { return channels_; }
  // Points of every block; with blocks of their own sizes, of all blocks together.
  size_t points() const { return points_; }
  size_t light_samples() const { return scales_.size(); }
  bool uniform_blocks() const { return block_first_.empty(); }
  // Points of one block.
  size_t block_points(size_t light_sample) const {
    return block_first_.empty() ? points_ : block_first_[light_sample + 1] - block_first_[light_sample];
  }
  size_t memory_bytes() const { return bytes_.size() + scales_.size() * sizeof(float); }
  // Bytes of one block of uniform blocks.
  size_t bytes_per_light_sample() const { return points_ * channels_ * precision_bytes(precision_); }

  // Adds weight * value of `point` of `light_sample` to out[0 .. channels).
  inline void add(size_t light_sample, size_t point, float weight, float* out) const;
  // One light sample's block, for StoredDecoding's inner loop.
  inline SampleBlock block(size_t light_sample) const;
  // Every value of one light sample, decoded (tests, the SH projection).
  std::vector<float> decode(size_t light_sample) const;

  // Raw form for the build cache.
  const std::vector<uint8_t>& bytes() const { return bytes_; }
  const std::vector<float>& scales() const { return scales_; }
  static StoredValues from_raw(Precision precision, int channels, bool signed_channels, size_t points,
                               std::vector<uint8_t> bytes, std::vector<float> scales);
  static StoredValues from_raw(Precision precision, int channels, bool signed_channels,
                               const std::vector<size_t>& block_points, std::vector<uint8_t> bytes,
                               std::vector<float> scales);
  bool signed_channels() const { return signed_; }

 private:
  Precision precision_ = Precision::float32;
  int channels_ = 0;
  bool signed_ = false;
  size_t points_ = 0;
  // Blocks of their own sizes: block b's first point (b = 0 .. light samples; the last, all points).
  // Empty when every block holds points_.
  std::vector<size_t> block_first_;
  std::vector<uint8_t> bytes_;
  std::vector<float> scales_;  // per light sample: the uint8 step; 1 otherwise
};

// One light sample's block as the lookup's inner loop reads it: the decoding chosen at compile time
// (StoredDecoding below), the block's first byte and its uint8 step, hoisted out of the per-point work.
struct SampleBlock {
  const uint8_t* bytes = nullptr;
  float scale = 1.0f;
};

// Reads one light sample's values for one precision (and sign, for uint8) known at compile time;
// `Channels` 0 reads the count from `channels`. The one definition of the decoding: StoredValues::add
// and the lookup's fused loops (lookup.h) both use it, so they agree bit for bit. A point adds
// factor(weight) x value(c) to each channel: for uint8 the weight times the step first, then each
// level, the order the stored builds' images and the Vulkan kernel have.
template <Precision P, bool Signed, int Channels>
struct StoredDecoding {
  static constexpr int channel_count = Channels;
  // The first value of `point` in the block.
  static inline const uint8_t* at(const SampleBlock& block, size_t point, int channels) {
    const size_t first = point * static_cast<size_t>(Channels > 0 ? Channels : channels);
    if constexpr (P == Precision::float32) return block.bytes + first * 4;
    if constexpr (P == Precision::float16) return block.bytes + first * 2;
    return block.bytes + first;
  }
  static inline float factor(const SampleBlock& block, float weight) {
    if constexpr (P == Precision::uint8) return weight * block.scale;
    return weight;
  }
  static inline float value(const uint8_t* values, int c) {
    if constexpr (P == Precision::float32) {
      float v;
      std::memcpy(&v, values + 4 * c, sizeof(v));
      return v;
    } else if constexpr (P == Precision::float16) {
      uint16_t half;
      std::memcpy(&half, values + 2 * c, sizeof(half));
      return half_to_float(half);
    } else if constexpr (Signed) {
      return static_cast<float>(static_cast<int8_t>(values[c]));
    } else {
      return static_cast<float>(values[c]);
    }
  }
  // out[c] += factor(weight) x value(c), c < channels.
  static inline void add(const SampleBlock& block, size_t point, float weight, int channels, float* out) {
    const int count = Channels > 0 ? Channels : channels;
    const uint8_t* values = at(block, point, channels);
    const float f = factor(block, weight);
    for (int c = 0; c < count; ++c) out[c] += f * value(values, c);
  }
};

inline SampleBlock StoredValues::block(size_t light_sample) const {
  const size_t first = block_first_.empty() ? light_sample * points_ : block_first_[light_sample];
  return SampleBlock{bytes_.data() + first * channels_ * precision_bytes(precision_), scales_[light_sample]};
}

inline void StoredValues::add(size_t light_sample, size_t point, float weight, float* out) const {
  const SampleBlock sample = block(light_sample);
  switch (precision_) {
    case Precision::float32:
      StoredDecoding<Precision::float32, false, 0>::add(sample, point, weight, channels_, out);
      break;
    case Precision::float16:
      StoredDecoding<Precision::float16, false, 0>::add(sample, point, weight, channels_, out);
      break;
    case Precision::uint8:
      if (signed_) {
        StoredDecoding<Precision::uint8, true, 0>::add(sample, point, weight, channels_, out);
      } else {
        StoredDecoding<Precision::uint8, false, 0>::add(sample, point, weight, channels_, out);
      }
      break;
  }
}

// Calls fn(StoredDecoding<...>{}) with the decoding of `values`, channels fixed at 3 or 9 (the two
// orientations) so that the lookup's loops unroll; any other count is read at run time.
template <class Function>
decltype(auto) with_decoding(const StoredValues& values, Function&& fn) {
  auto by_channels = [&](auto precision, auto is_signed) -> decltype(auto) {
    constexpr Precision P = decltype(precision)::value;
    constexpr bool S = decltype(is_signed)::value;
    if (values.channels() == 3) return fn(StoredDecoding<P, S, 3>{});
    if (values.channels() == 9) return fn(StoredDecoding<P, S, 9>{});
    return fn(StoredDecoding<P, S, 0>{});
  };
  using Float32 = std::integral_constant<Precision, Precision::float32>;
  using Float16 = std::integral_constant<Precision, Precision::float16>;
  using Uint8 = std::integral_constant<Precision, Precision::uint8>;
  switch (values.precision()) {
    case Precision::float32: return by_channels(Float32{}, std::false_type{});
    case Precision::float16: return by_channels(Float16{}, std::false_type{});
    case Precision::uint8:
      break;
  }
  if (values.signed_channels()) return by_channels(Uint8{}, std::true_type{});
  return by_channels(Uint8{}, std::false_type{});
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

}  // namespace causticbench
