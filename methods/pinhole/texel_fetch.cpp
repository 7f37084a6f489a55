// The vector fetch of the unfiltered reflection kernel (declared in texel_fetch.h).
#include "methods/pinhole/texel_fetch.h"

#include <cstdlib>

#include "methods/common/simd_lanes.h"
#include "methods/pinhole/packed_texels.h"
#include "methods/pinhole/throughput.h"

namespace causticbench {

bool vector_fetch_enabled() {
  return simd::has_avx2() && std::getenv("CAUSTICBENCH_PINHOLE_SCALAR_FETCH") == nullptr;
}

namespace {

CAUSTICBENCH_AVX2 inline __m256 gather(const float* base, __m256i offsets) {
  return _mm256_i32gather_ps(base, offsets, 4);
}

// glm::mix(a, b, w) = a (1 - w) + b w, as the scalar lookup computes it.
CAUSTICBENCH_AVX2 inline __m256 mix(__m256 a, __m256 b, __m256 w) {
  return _mm256_add_ps(_mm256_mul_ps(a, _mm256_sub_ps(_mm256_set1_ps(1.0f), w)), _mm256_mul_ps(b, w));
}

// The float offset of texel (x, y) of the face starting at `base`, RGB interleaved.
CAUSTICBENCH_AVX2 inline __m256i texel_offset(__m256i base, __m256i x, __m256i y, __m256i resolution) {
  return _mm256_add_epi32(base, _mm256_mullo_epi32(_mm256_add_epi32(_mm256_mullo_epi32(y, resolution), x),
                                                   _mm256_set1_epi32(3)));
}

CAUSTICBENCH_AVX2 inline float horizontal_sum(__m256 v) {
  __m128 low = _mm256_castps256_ps128(v), high = _mm256_extractf128_ps(v, 1);
  __m128 four = _mm_add_ps(low, high);
  __m128 two = _mm_add_ps(four, _mm_movehl_ps(four, four));
  return _mm_cvtss_f32(_mm_add_ss(two, _mm_shuffle_ps(two, two, 1)));
}

// One bilinear corner from the shared-exponent map: the corner's scale 2^(e + offset) (its exponent added
// to the unit's float bits) times its weight, then each mantissa times that.
CAUSTICBENCH_AVX2 inline void add_packed_corner(const uint32_t* packed, __m256i index, __m256 weight, __m256i unit_bits,
                                                __m256i mantissa_mask, __m256 radiance[3]) {
  const __m256i texel = _mm256_i32gather_epi32(reinterpret_cast<const int*>(packed), index, 4);
  const __m256 scale = _mm256_castsi256_ps(
      _mm256_add_epi32(_mm256_slli_epi32(_mm256_srli_epi32(texel, PackedTexels::kExponentShift), 23), unit_bits));
  const __m256 scaled = _mm256_mul_ps(scale, weight);
  for (int channel = 0; channel < 3; ++channel) {
    const __m256i mantissa = _mm256_and_si256(_mm256_srli_epi32(texel, channel * PackedTexels::kMantissaBits), mantissa_mask);
    radiance[channel] = _mm256_add_ps(radiance[channel], _mm256_mul_ps(_mm256_cvtepi32_ps(mantissa), scaled));
  }
}

// The fetch of `whole` samples (a multiple of 8): through b.indices (gathers) or, with kCompacted, the
// first `whole` entries of the arrays themselves (loads).
template <bool kCompacted>
CAUSTICBENCH_AVX2 inline Color fetch_lanes(const FetchBlock& b, size_t whole) {
  const __m256 zero = _mm256_setzero_ps(), half = _mm256_set1_ps(0.5f), one = _mm256_set1_ps(1.0f);
  const __m256 last_texel = _mm256_set1_ps(static_cast<float>(b.resolution) - 1.0f);
  const __m256i last_index = _mm256_set1_epi32(b.resolution - 1), one_index = _mm256_set1_epi32(1);
  const __m256i resolution = _mm256_set1_epi32(b.resolution), three = _mm256_set1_epi32(3);  // RGB
  const __m256i face_size = _mm256_set1_epi32(b.resolution * b.resolution * 3);
  const __m256i face_texels = _mm256_set1_epi32(b.resolution * b.resolution);
  const __m256i unit_bits = _mm256_set1_epi32(b.unit_bits);
  const __m256i mantissa_mask = _mm256_set1_epi32(static_cast<int>(PackedTexels::kMantissaMask));
  const __m256 entries = _mm256_set1_ps(static_cast<float>(ThroughputTable::kEntries - 1));
  const __m256i table_size = _mm256_set1_epi32((ThroughputTable::kEntries + 1) * 3);
  __m256 red = zero, green = zero, blue = zero;
  for (size_t k = 0; k < whole; k += 8) {
    __m256i j = _mm256_setzero_si256(), face;
    __m256 s, t, w, c;
    if constexpr (kCompacted) {
      face = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(b.face + k));
      s = _mm256_loadu_ps(b.texel_s + k), t = _mm256_loadu_ps(b.texel_t + k), w = _mm256_loadu_ps(b.weight + k);
      c = _mm256_loadu_ps(b.cos_sample + k);
    } else {
      j = _mm256_cvtepu16_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(b.indices + k)));
      face = _mm256_i32gather_epi32(b.face, j, 4);
      s = gather(b.texel_s, j), t = gather(b.texel_t, j), w = gather(b.weight, j);
      c = gather(b.cos_sample, j);
    }
    // LightCubeMap::lookup_texel: clamp, first texel, neighbours clamped to the face, weights.
    const __m256 fx = _mm256_min_ps(_mm256_max_ps(_mm256_sub_ps(s, half), zero), last_texel);
    const __m256 fy = _mm256_min_ps(_mm256_max_ps(_mm256_sub_ps(t, half), zero), last_texel);
    const __m256i x0 = _mm256_cvttps_epi32(fx), y0 = _mm256_cvttps_epi32(fy);
    const __m256i x1 = _mm256_min_epi32(_mm256_add_epi32(x0, one_index), last_index);
    const __m256i y1 = _mm256_min_epi32(_mm256_add_epi32(y0, one_index), last_index);
    const __m256 wx = _mm256_sub_ps(fx, _mm256_cvtepi32_ps(x0)), wy = _mm256_sub_ps(fy, _mm256_cvtepi32_ps(y0));
    const __m256i base = _mm256_mullo_epi32(face, face_size);
    __m256 radiance[3];
    if (b.packed) {
      // Shared exponent (packed_texels.h): four gathers, the corners weighted as glm::mix weights them.
      const __m256i base_texel = _mm256_mullo_epi32(face, face_texels);
      const __m256i i00 = _mm256_add_epi32(base_texel, _mm256_add_epi32(_mm256_mullo_epi32(y0, resolution), x0));
      const __m256i i10 = _mm256_add_epi32(i00, _mm256_sub_epi32(x1, x0));
      const __m256i row = _mm256_mullo_epi32(_mm256_sub_epi32(y1, y0), resolution);
      const __m256i i01 = _mm256_add_epi32(i00, row), i11 = _mm256_add_epi32(i10, row);
      const __m256 ux = _mm256_sub_ps(one, wx), uy = _mm256_sub_ps(one, wy);
      radiance[0] = radiance[1] = radiance[2] = zero;
      add_packed_corner(b.packed, i00, _mm256_mul_ps(ux, uy), unit_bits, mantissa_mask, radiance);
      add_packed_corner(b.packed, i10, _mm256_mul_ps(wx, uy), unit_bits, mantissa_mask, radiance);
      add_packed_corner(b.packed, i01, _mm256_mul_ps(ux, wy), unit_bits, mantissa_mask, radiance);
      add_packed_corner(b.packed, i11, _mm256_mul_ps(wx, wy), unit_bits, mantissa_mask, radiance);
    } else {
      const __m256i o00 = texel_offset(base, x0, y0, resolution), o10 = texel_offset(base, x1, y0, resolution);
      const __m256i o01 = texel_offset(base, x0, y1, resolution), o11 = texel_offset(base, x1, y1, resolution);
      for (int channel = 0; channel < 3; ++channel) {
        const float* texels = b.texels + channel;
        radiance[channel] = mix(mix(gather(texels, o00), gather(texels, o10), wx),
                                mix(gather(texels, o01), gather(texels, o11), wx), wy);
      }
    }
    // ThroughputTable::operator(): clamp, index, blend.
    const __m256 position = _mm256_mul_ps(_mm256_min_ps(_mm256_max_ps(c, zero), one), entries);
    const __m256i index = _mm256_cvttps_epi32(position);
    const __m256 fraction = _mm256_sub_ps(position, _mm256_cvtepi32_ps(index));
    __m256i table = _mm256_setzero_si256();  // one material: its table, without a gather
    if (!b.one_table) {
      table = kCompacted ? _mm256_loadu_si256(reinterpret_cast<const __m256i*>(b.table_of + k))
                         : _mm256_i32gather_epi32(b.table_of, j, 4);
    }
    const __m256i at = _mm256_add_epi32(_mm256_mullo_epi32(table, table_size), _mm256_mullo_epi32(index, three));
    __m256 contribution[3];
    for (int channel = 0; channel < 3; ++channel) {
      const __m256 low = gather(b.throughput + channel, at), high = gather(b.throughput + 3 + channel, at);
      const __m256 throughput = _mm256_add_ps(low, _mm256_mul_ps(_mm256_sub_ps(high, low), fraction));
      contribution[channel] = _mm256_mul_ps(_mm256_mul_ps(radiance[channel], throughput), w);
    }
    red = _mm256_add_ps(red, contribution[0]);
    green = _mm256_add_ps(green, contribution[1]);
    blue = _mm256_add_ps(blue, contribution[2]);
  }
  return Color(horizontal_sum(red), horizontal_sum(green), horizontal_sum(blue));
}

// For each mask of 8 lanes, the lanes that are set, first (AVX2's left-packing permutation).
struct LeftPack {
  alignas(32) int32_t lanes[256][8];
  LeftPack() {
    for (int mask = 0; mask < 256; ++mask) {
      int count = 0;
      for (int lane = 0; lane < 8; ++lane)
        if (mask >> lane & 1) lanes[mask][count++] = lane;
      for (; count < 8; ++count) lanes[mask][count] = 0;
    }
  }
};

// Eight values (floats, or ints as their bits), the lanes `order` names first.
CAUSTICBENCH_AVX2 inline void left_pack(const float* from, __m256i order, float* to) {
  _mm256_storeu_ps(to, _mm256_permutevar8x32_ps(_mm256_loadu_ps(from), order));
}

}  // namespace

CAUSTICBENCH_AVX2 size_t fetch_sum_avx2(const FetchBlock& b, Color& sum) {
  if (b.indices) {
    const size_t whole = b.count / 8 * 8;
    sum += fetch_lanes<false>(b, whole);
    return whole;
  }
  // Every sample of the block, compacted here eight at a time by a permutation rather than one by one:
  // the facing ones (weight > 0) first, then padding of weight 0 up to a multiple of 8.
  static const LeftPack pack;
  constexpr size_t kMost = 256;
  if (b.count > kMost || b.count % 8 != 0) std::abort();  // the caller's blocks are 256 samples
  alignas(32) int face[kMost + 8], table[kMost + 8];
  alignas(32) float s[kMost + 8], t[kMost + 8], w[kMost + 8], c[kMost + 8];
  size_t facing = 0;
  for (size_t k = 0; k < b.count; k += 8) {
    const __m256 weight = _mm256_loadu_ps(b.weight + k);
    const int mask = _mm256_movemask_ps(_mm256_cmp_ps(weight, _mm256_setzero_ps(), _CMP_GT_OQ));
    const __m256i order = _mm256_load_si256(reinterpret_cast<const __m256i*>(pack.lanes[mask]));
    _mm256_storeu_ps(w + facing, _mm256_permutevar8x32_ps(weight, order));
    left_pack(b.texel_s + k, order, s + facing), left_pack(b.texel_t + k, order, t + facing);
    left_pack(b.cos_sample + k, order, c + facing);
    left_pack(reinterpret_cast<const float*>(b.face + k), order, reinterpret_cast<float*>(face + facing));
    if (!b.one_table) left_pack(reinterpret_cast<const float*>(b.table_of + k), order, reinterpret_cast<float*>(table + facing));
    facing += static_cast<size_t>(__builtin_popcount(mask));
  }
  const size_t whole = (facing + 7) / 8 * 8;
  for (size_t k = facing; k < whole; ++k) face[k] = 0, table[k] = 0, s[k] = t[k] = 0.5f, w[k] = c[k] = 0.0f;
  FetchBlock compacted = b;
  compacted.face = face, compacted.table_of = table, compacted.texel_s = s, compacted.texel_t = t;
  compacted.weight = w, compacted.cos_sample = c;
  sum += fetch_lanes<true>(compacted, whole);
  return b.count;
}

}  // namespace causticbench
