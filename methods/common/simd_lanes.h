// The vector lanes the CPU kernels share (pinhole's reflection_lanes.cpp, csl's evaluation_lanes.cpp):
// float and double vectors with the few operations the kernels need, each for SSE2 (part of every
// x86-64) and AVX2 (used where the processor has it, checked at run time by has_avx2()). A kernel is a
// template over one of these structs, instantiated once plainly and once inside a CAUSTICBENCH_AVX2
// function.
#pragma once

#include <immintrin.h>

#include <cstddef>

#define CAUSTICBENCH_AVX2 __attribute__((target("avx2")))

namespace causticbench::simd {

#define CAUSTICBENCH_SIMD_OPS(PREFIX, SUFFIX, VEC, SCALAR, ATTRIBUTE)                                     \
  ATTRIBUTE static VEC set1(SCALAR v) { return PREFIX##_set1_##SUFFIX(v); }                              \
  ATTRIBUTE static VEC load(const SCALAR* p) { return PREFIX##_loadu_##SUFFIX(p); }                      \
  ATTRIBUTE static void store(SCALAR* p, VEC v) { PREFIX##_storeu_##SUFFIX(p, v); }                      \
  ATTRIBUTE static VEC add(VEC a, VEC b) { return PREFIX##_add_##SUFFIX(a, b); }                         \
  ATTRIBUTE static VEC sub(VEC a, VEC b) { return PREFIX##_sub_##SUFFIX(a, b); }                         \
  ATTRIBUTE static VEC mul(VEC a, VEC b) { return PREFIX##_mul_##SUFFIX(a, b); }                         \
  ATTRIBUTE static VEC div(VEC a, VEC b) { return PREFIX##_div_##SUFFIX(a, b); }                         \
  ATTRIBUTE static VEC sqrt(VEC a) { return PREFIX##_sqrt_##SUFFIX(a); }                                 \
  ATTRIBUTE static VEC bit_and(VEC a, VEC b) { return PREFIX##_and_##SUFFIX(a, b); }                     \
  ATTRIBUTE static VEC bit_or(VEC a, VEC b) { return PREFIX##_or_##SUFFIX(a, b); }                       \
  ATTRIBUTE static VEC and_not(VEC a, VEC b) { return PREFIX##_andnot_##SUFFIX(a, b); }                  \
  ATTRIBUTE static VEC bit_xor(VEC a, VEC b) { return PREFIX##_xor_##SUFFIX(a, b); }                     \
  ATTRIBUTE static VEC select(VEC mask, VEC a, VEC b) {                                                  \
    return PREFIX##_or_##SUFFIX(PREFIX##_and_##SUFFIX(mask, a), PREFIX##_andnot_##SUFFIX(mask, b));      \
  }                                                                                                      \
  /* max and min return the second operand when the first is NaN: clamps turn NaN into a bound. */     \
  ATTRIBUTE static VEC max(VEC a, VEC b) { return PREFIX##_max_##SUFFIX(a, b); }                         \
  ATTRIBUTE static VEC min(VEC a, VEC b) { return PREFIX##_min_##SUFFIX(a, b); }                         \
  /* One bit per lane, lane 0 the lowest: which lanes of a comparison's mask are set. */                \
  ATTRIBUTE static int lanes(VEC mask) { return PREFIX##_movemask_##SUFFIX(mask); }

// Four float lanes.
struct Sse {
  using Vec = __m128;
  using Scalar = float;
  static constexpr size_t width = 4;
  CAUSTICBENCH_SIMD_OPS(_mm, ps, __m128, float, )
  static Vec less(Vec a, Vec b) { return _mm_cmplt_ps(a, b); }
  static Vec less_equal(Vec a, Vec b) { return _mm_cmple_ps(a, b); }
  static Vec greater(Vec a, Vec b) { return _mm_cmpgt_ps(a, b); }
  static Vec greater_equal(Vec a, Vec b) { return _mm_cmpge_ps(a, b); }
  static Vec equal(Vec a, Vec b) { return _mm_cmpeq_ps(a, b); }
  static Vec unordered(Vec a, Vec b) { return _mm_cmpunord_ps(a, b); }
  static void store_int(int* p, Vec v) { _mm_storeu_si128(reinterpret_cast<__m128i*>(p), _mm_cvttps_epi32(v)); }
  static Vec truncate(Vec v) { return _mm_cvtepi32_ps(_mm_cvttps_epi32(v)); }
  // The lanes widened to doubles, stored at p[0..width).
  static void store_double(double* p, Vec v) {
    _mm_storeu_pd(p, _mm_cvtps_pd(v));
    _mm_storeu_pd(p + 2, _mm_cvtps_pd(_mm_movehl_ps(v, v)));
  }
};

// Eight float lanes.
struct Avx2 {
  using Vec = __m256;
  using Scalar = float;
  static constexpr size_t width = 8;
  CAUSTICBENCH_SIMD_OPS(_mm256, ps, __m256, float, CAUSTICBENCH_AVX2)
  CAUSTICBENCH_AVX2 static Vec less(Vec a, Vec b) { return _mm256_cmp_ps(a, b, _CMP_LT_OQ); }
  CAUSTICBENCH_AVX2 static Vec less_equal(Vec a, Vec b) { return _mm256_cmp_ps(a, b, _CMP_LE_OQ); }
  CAUSTICBENCH_AVX2 static Vec greater(Vec a, Vec b) { return _mm256_cmp_ps(a, b, _CMP_GT_OQ); }
  CAUSTICBENCH_AVX2 static Vec greater_equal(Vec a, Vec b) { return _mm256_cmp_ps(a, b, _CMP_GE_OQ); }
  CAUSTICBENCH_AVX2 static Vec equal(Vec a, Vec b) { return _mm256_cmp_ps(a, b, _CMP_EQ_OQ); }
  CAUSTICBENCH_AVX2 static Vec unordered(Vec a, Vec b) { return _mm256_cmp_ps(a, b, _CMP_UNORD_Q); }
  CAUSTICBENCH_AVX2 static void store_int(int* p, Vec v) {
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(p), _mm256_cvttps_epi32(v));
  }
  CAUSTICBENCH_AVX2 static Vec truncate(Vec v) { return _mm256_round_ps(v, _MM_FROUND_TO_ZERO | _MM_FROUND_NO_EXC); }
  CAUSTICBENCH_AVX2 static void store_double(double* p, Vec v) {
    _mm256_storeu_pd(p, _mm256_cvtps_pd(_mm256_castps256_ps128(v)));
    _mm256_storeu_pd(p + 4, _mm256_cvtps_pd(_mm256_extractf128_ps(v, 1)));
  }
};

// Two double lanes.
struct SseDouble {
  using Vec = __m128d;
  using Scalar = double;
  static constexpr size_t width = 2;
  CAUSTICBENCH_SIMD_OPS(_mm, pd, __m128d, double, )
  static Vec less(Vec a, Vec b) { return _mm_cmplt_pd(a, b); }
  static Vec less_equal(Vec a, Vec b) { return _mm_cmple_pd(a, b); }
  static Vec greater(Vec a, Vec b) { return _mm_cmpgt_pd(a, b); }
  static Vec greater_equal(Vec a, Vec b) { return _mm_cmpge_pd(a, b); }
  static Vec equal(Vec a, Vec b) { return _mm_cmpeq_pd(a, b); }
  static Vec not_equal(Vec a, Vec b) { return _mm_cmpneq_pd(a, b); }
  static void store_double(double* p, Vec v) { store(p, v); }
};

// Four double lanes.
struct Avx2Double {
  using Vec = __m256d;
  using Scalar = double;
  static constexpr size_t width = 4;
  CAUSTICBENCH_SIMD_OPS(_mm256, pd, __m256d, double, CAUSTICBENCH_AVX2)
  CAUSTICBENCH_AVX2 static Vec less(Vec a, Vec b) { return _mm256_cmp_pd(a, b, _CMP_LT_OQ); }
  CAUSTICBENCH_AVX2 static Vec less_equal(Vec a, Vec b) { return _mm256_cmp_pd(a, b, _CMP_LE_OQ); }
  CAUSTICBENCH_AVX2 static Vec greater(Vec a, Vec b) { return _mm256_cmp_pd(a, b, _CMP_GT_OQ); }
  CAUSTICBENCH_AVX2 static Vec greater_equal(Vec a, Vec b) { return _mm256_cmp_pd(a, b, _CMP_GE_OQ); }
  CAUSTICBENCH_AVX2 static Vec equal(Vec a, Vec b) { return _mm256_cmp_pd(a, b, _CMP_EQ_OQ); }
  CAUSTICBENCH_AVX2 static Vec not_equal(Vec a, Vec b) { return _mm256_cmp_pd(a, b, _CMP_NEQ_UQ); }
  CAUSTICBENCH_AVX2 static void store_double(double* p, Vec v) { store(p, v); }
};

#undef CAUSTICBENCH_SIMD_OPS

// Whether this processor runs the AVX2 lanes (checked once).
inline bool has_avx2() {
  static const bool available = __builtin_cpu_supports("avx2");
  return available;
}

}  // namespace causticbench::simd
