// The gathered image lookups of csl's CPU backend (declared in tile_lookup.h). Each step mirrors a line
// of IntensityImage::lookup (spot_light.cpp), StoredImage::lookup (spot_light.h) or tile_value
// (evaluation_lanes.h).
#include "methods/csl/tile_lookup.h"

#include "methods/common/simd_lanes.h"

namespace causticbench::csl {

namespace {

// The lanes whose bit is set in `bits`, as a mask of all-ones lanes.
CAUSTICBENCH_AVX2 inline __m256 lane_mask(uint32_t bits) {
  const __m256i single = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
  return _mm256_castsi256_ps(_mm256_cmpeq_epi32(_mm256_and_si256(_mm256_set1_epi32(static_cast<int>(bits)), single), single));
}

// Eight doubles (two AVX vectors) rounded to floats, as static_cast<float> rounds them.
CAUSTICBENCH_AVX2 inline __m256 to_float(const double* values) {
  return _mm256_set_m128(_mm256_cvtpd_ps(_mm256_loadu_pd(values + 4)), _mm256_cvtpd_ps(_mm256_loadu_pd(values)));
}

// Bits of the lanes of `values` (eight doubles) that are not greater than `half` in magnitude: NaN
// passes, as StoredImage::lookup's `fabs(x) > half` lets it through.
CAUSTICBENCH_AVX2 inline uint32_t within(const double* values, __m256d half) {
  const __m256d magnitude = _mm256_set1_pd(-0.0);
  const __m256d low = _mm256_andnot_pd(magnitude, _mm256_loadu_pd(values));
  const __m256d high = _mm256_andnot_pd(magnitude, _mm256_loadu_pd(values + 4));
  return static_cast<uint32_t>(_mm256_movemask_pd(_mm256_cmp_pd(low, half, _CMP_NGT_UQ))) |
         static_cast<uint32_t>(_mm256_movemask_pd(_mm256_cmp_pd(high, half, _CMP_NGT_UQ))) << 4;
}

// The four corners' texels of the bilinear squares at row-major texel `index` (i0 + j0 size), for the
// lanes of `interior` (whose squares lie inside the image): uint16 codes times the scale, or floats.
struct Corners {
  __m256 t00, t10, t01, t11;
};

CAUSTICBENCH_AVX2 inline Corners gather_corners(const IntensityImage& image, __m256i index, __m256 interior) {
  Corners corners;
  const __m256i size = _mm256_set1_epi32(image.size());
  const __m256i mask = _mm256_castps_si256(interior);
  if (image.precision() == IntensityImage::Precision::uint16) {
    // One 32-bit gather reads a texel and its right-hand neighbour (i0 + 1 < size: inside the row).
    const int* codes = reinterpret_cast<const int*>(image.quantised().data());
    const __m256i zero = _mm256_setzero_si256(), low_half = _mm256_set1_epi32(0xFFFF);
    const __m256i row0 = _mm256_mask_i32gather_epi32(zero, codes, index, mask, 2);
    const __m256i row1 = _mm256_mask_i32gather_epi32(zero, codes, _mm256_add_epi32(index, size), mask, 2);
    const __m256 scale = _mm256_set1_ps(image.scales()[0]);
    // texel(): the code (an int) times the scale, in float.
    corners.t00 = _mm256_mul_ps(_mm256_cvtepi32_ps(_mm256_and_si256(row0, low_half)), scale);
    corners.t10 = _mm256_mul_ps(_mm256_cvtepi32_ps(_mm256_srli_epi32(row0, 16)), scale);
    corners.t01 = _mm256_mul_ps(_mm256_cvtepi32_ps(_mm256_and_si256(row1, low_half)), scale);
    corners.t11 = _mm256_mul_ps(_mm256_cvtepi32_ps(_mm256_srli_epi32(row1, 16)), scale);
  } else {
    const float* texels = image.floats().data();
    const __m256 zero = _mm256_setzero_ps();
    const __m256i right = _mm256_set1_epi32(1), below = _mm256_add_epi32(index, size);
    corners.t00 = _mm256_mask_i32gather_ps(zero, texels, index, interior, 4);
    corners.t10 = _mm256_mask_i32gather_ps(zero, texels, _mm256_add_epi32(index, right), interior, 4);
    corners.t01 = _mm256_mask_i32gather_ps(zero, texels, below, interior, 4);
    corners.t11 = _mm256_mask_i32gather_ps(zero, texels, _mm256_add_epi32(below, right), interior, 4);
  }
  return corners;
}

// tile_value's addition of one ray, value[i] += float(read * correction * cosine), for one lane whose
// bilinear square reaches beyond the image's texels: IntensityImage::lookup itself.
void add_one(const IntensityImage& image, const TileRays& rays, int k, size_t i, float* value) {
  float read;
  if (!StoredImage(image).lookup(rays.x[k][i], rays.y[k][i], &read)) return;
  value[i] += static_cast<float>(read * rays.correction[k][i] * rays.cosine[k][i]);
}

CAUSTICBENCH_AVX2 __attribute__((flatten)) void tile_lookups_avx2(const IntensityImage& image, const TileRays& rays,
                                                                 size_t count, float* value) {
  const uint32_t points = (1u << count) - 1u;
  const float half = image.half_size();
  const __m256d half_double = _mm256_set1_pd(static_cast<double>(half));
  const __m256 half_float = _mm256_set1_ps(half), scale = _mm256_set1_ps(image.size() / (2.0f * half));
  const __m256 zero = _mm256_setzero_ps(), one = _mm256_set1_ps(1.0f), minus_one = _mm256_set1_ps(-1.0f);
  const __m256 size = _mm256_set1_ps(static_cast<float>(image.size()));
  const __m256 last_square = _mm256_set1_ps(static_cast<float>(image.size() - 2));
  const __m256i row = _mm256_set1_epi32(image.size());
  __m256 sum = _mm256_loadu_ps(value);
  // Candidate by candidate, as tile_value adds them per point.
  for (int k = 0; k < TileRays::kCandidates; ++k) {
    // StoredImage::lookup: a ray beyond the image's square adds nothing.
    const uint32_t active = rays.ray[k] & points & within(rays.x[k], half_double) & within(rays.y[k], half_double);
    if (active == 0) continue;
    // IntensityImage::lookup, in float.
    const __m256 fx = _mm256_sub_ps(_mm256_mul_ps(_mm256_add_ps(to_float(rays.x[k]), half_float), scale), _mm256_set1_ps(0.5f));
    const __m256 fy = _mm256_sub_ps(_mm256_mul_ps(_mm256_add_ps(to_float(rays.y[k]), half_float), scale), _mm256_set1_ps(0.5f));
    const __m256 inside = _mm256_and_ps(_mm256_and_ps(_mm256_cmp_ps(fx, minus_one, _CMP_GT_OQ), _mm256_cmp_ps(fy, minus_one, _CMP_GT_OQ)),
                                        _mm256_and_ps(_mm256_cmp_ps(fx, size, _CMP_LT_OQ), _mm256_cmp_ps(fy, size, _CMP_LT_OQ)));
    const __m256 x0 = _mm256_floor_ps(fx), y0 = _mm256_floor_ps(fy);
    // The square's four texels all exist: i0 and j0 in [0, size - 2].
    const __m256 interior = _mm256_and_ps(
        _mm256_and_ps(lane_mask(active), inside),
        _mm256_and_ps(_mm256_and_ps(_mm256_cmp_ps(x0, zero, _CMP_GE_OQ), _mm256_cmp_ps(x0, last_square, _CMP_LE_OQ)),
                      _mm256_and_ps(_mm256_cmp_ps(y0, zero, _CMP_GE_OQ), _mm256_cmp_ps(y0, last_square, _CMP_LE_OQ))));
    const uint32_t gathered = static_cast<uint32_t>(_mm256_movemask_ps(interior));
    const uint32_t outside = active & ~static_cast<uint32_t>(_mm256_movemask_ps(inside));  // lookup reads zeros
    const uint32_t border = active & ~gathered & ~outside;
    const __m256i index = _mm256_add_epi32(_mm256_mullo_epi32(_mm256_cvttps_epi32(y0), row), _mm256_cvttps_epi32(x0));
    const Corners c = gather_corners(image, index, interior);
    const __m256 tx = _mm256_sub_ps(fx, x0), ty = _mm256_sub_ps(fy, y0);
    const __m256 sx = _mm256_sub_ps(one, tx), sy = _mm256_sub_ps(one, ty);
    __m256 read = _mm256_add_ps(zero, _mm256_mul_ps(_mm256_mul_ps(sx, sy), c.t00));
    read = _mm256_add_ps(read, _mm256_mul_ps(_mm256_mul_ps(tx, sy), c.t10));
    read = _mm256_add_ps(read, _mm256_mul_ps(_mm256_mul_ps(sx, ty), c.t01));
    read = _mm256_add_ps(read, _mm256_mul_ps(_mm256_mul_ps(tx, ty), c.t11));
    read = _mm256_and_ps(read, interior);  // the lanes outside the texels read zero
    // tile_value: value += float(read * correction * cosine), the product in double.
    const __m256d low = _mm256_mul_pd(_mm256_mul_pd(_mm256_cvtps_pd(_mm256_castps256_ps128(read)), _mm256_loadu_pd(rays.correction[k])),
                                      _mm256_loadu_pd(rays.cosine[k]));
    const __m256d high = _mm256_mul_pd(_mm256_mul_pd(_mm256_cvtps_pd(_mm256_extractf128_ps(read, 1)), _mm256_loadu_pd(rays.correction[k] + 4)),
                                       _mm256_loadu_pd(rays.cosine[k] + 4));
    const __m256 added = _mm256_add_ps(sum, _mm256_set_m128(_mm256_cvtpd_ps(high), _mm256_cvtpd_ps(low)));
    sum = _mm256_blendv_ps(sum, added, lane_mask(gathered | outside));
    if (border != 0) {
      alignas(32) float lanes[8];
      _mm256_store_ps(lanes, sum);
      for (size_t i = 0; i < count; ++i) {
        if ((border >> i) & 1u) add_one(image, rays, k, i, lanes);
      }
      sum = _mm256_load_ps(lanes);
    }
  }
  alignas(32) float lanes[8];
  _mm256_store_ps(lanes, sum);
  for (size_t i = 0; i < count; ++i) value[i] = lanes[i];
}

}  // namespace

bool tile_lookups_apply(const IntensityImage& image) { return image.channels() == 1 && image.size() >= 2 && simd::has_avx2(); }

void tile_lookups(const IntensityImage& image, const TileRays& rays, size_t count, float* value) {
  tile_lookups_avx2(image, rays, count, value);
}

}  // namespace causticbench::csl
