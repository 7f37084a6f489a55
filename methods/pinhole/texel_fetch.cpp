// The vector fetch of the unfiltered reflection kernel (declared in texel_fetch.h).
#include "methods/pinhole/texel_fetch.h"

#include <immintrin.h>

#include <cstdlib>

#include "methods/pinhole/throughput.h"

namespace causticbench {

bool vector_fetch_enabled() {
  static const bool available = __builtin_cpu_supports("avx2");
  return available && std::getenv("CAUSTICBENCH_PINHOLE_SCALAR_FETCH") == nullptr;
}

namespace {

#define CAUSTICBENCH_AVX2 __attribute__((target("avx2")))

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

}  // namespace

CAUSTICBENCH_AVX2 size_t fetch_sum_avx2(const FetchBlock& b, Color& sum) {
  const size_t whole = b.count / 8 * 8;
  const __m256 zero = _mm256_setzero_ps(), half = _mm256_set1_ps(0.5f), one = _mm256_set1_ps(1.0f);
  const __m256 last_texel = _mm256_set1_ps(static_cast<float>(b.resolution) - 1.0f);
  const __m256i last_index = _mm256_set1_epi32(b.resolution - 1), one_index = _mm256_set1_epi32(1);
  const __m256i resolution = _mm256_set1_epi32(b.resolution), three = _mm256_set1_epi32(3);  // RGB
  const __m256i face_size = _mm256_set1_epi32(b.resolution * b.resolution * 3);
  const __m256 entries = _mm256_set1_ps(static_cast<float>(ThroughputTable::kEntries - 1));
  const __m256i table_size = _mm256_set1_epi32((ThroughputTable::kEntries + 1) * 3);
  __m256 red = zero, green = zero, blue = zero;
  for (size_t k = 0; k < whole; k += 8) {
    const __m256i j = _mm256_cvtepu16_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(b.indices + k)));
    const __m256i face = _mm256_i32gather_epi32(b.face, j, 4);
    const __m256 s = gather(b.texel_s, j), t = gather(b.texel_t, j), w = gather(b.weight, j);
    const __m256 c = gather(b.cos_sample, j);
    // LightCubeMap::lookup_texel: clamp, first texel, neighbours clamped to the face, weights.
    const __m256 fx = _mm256_min_ps(_mm256_max_ps(_mm256_sub_ps(s, half), zero), last_texel);
    const __m256 fy = _mm256_min_ps(_mm256_max_ps(_mm256_sub_ps(t, half), zero), last_texel);
    const __m256i x0 = _mm256_cvttps_epi32(fx), y0 = _mm256_cvttps_epi32(fy);
    const __m256i x1 = _mm256_min_epi32(_mm256_add_epi32(x0, one_index), last_index);
    const __m256i y1 = _mm256_min_epi32(_mm256_add_epi32(y0, one_index), last_index);
    const __m256 wx = _mm256_sub_ps(fx, _mm256_cvtepi32_ps(x0)), wy = _mm256_sub_ps(fy, _mm256_cvtepi32_ps(y0));
    const __m256i base = _mm256_mullo_epi32(face, face_size);
    const __m256i o00 = texel_offset(base, x0, y0, resolution), o10 = texel_offset(base, x1, y0, resolution);
    const __m256i o01 = texel_offset(base, x0, y1, resolution), o11 = texel_offset(base, x1, y1, resolution);
    __m256 radiance[3];
    for (int channel = 0; channel < 3; ++channel) {
      const float* texels = b.texels + channel;
      radiance[channel] = mix(mix(gather(texels, o00), gather(texels, o10), wx),
                              mix(gather(texels, o01), gather(texels, o11), wx), wy);
    }
    // ThroughputTable::operator(): clamp, index, blend.
    const __m256 position = _mm256_mul_ps(_mm256_min_ps(_mm256_max_ps(c, zero), one), entries);
    const __m256i index = _mm256_cvttps_epi32(position);
    const __m256 fraction = _mm256_sub_ps(position, _mm256_cvtepi32_ps(index));
    const __m256i table = _mm256_i32gather_epi32(b.table_of, j, 4);
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
  sum += Color(horizontal_sum(red), horizontal_sum(green), horizontal_sum(blue));
  return whole;
}

}  // namespace causticbench
