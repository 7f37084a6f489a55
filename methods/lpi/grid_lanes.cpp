// The grid lookup in AVX2 lanes (declared in grid_lanes.h). Each step names the scalar line of
// lookup.h / grid_layout.h it repeats; the operand order of every addition and multiplication is the
// scalar one, which is what keeps the images bit for bit equal.
#include "methods/lpi/grid_lanes.h"

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <limits>

#include "methods/common/simd_lanes.h"
#include "methods/lpi/lookup.h"

namespace causticbench::lpi {

namespace {

using simd::Avx2;

// AVX2 and F16C (float16 values); AVX2 processors have F16C in practice, but both are checked.
#define LANES_TARGET __attribute__((target("avx2,f16c")))
bool lanes_available() {
  static const bool available = simd::has_avx2() && __builtin_cpu_supports("f16c");
  return available;
}
using V = __m256;
using Lanes = __m256i;
constexpr int kWidth = 8;

// One unrotated read as the lanes take it: its block, weight and uint8 step, and the last byte
// offset (from the block's first byte) at which uint8's 4-byte gathers stay inside the stored values.
struct LaneRead {
  const uint8_t* bytes = nullptr;
  float weight = 0.0f;
  float scale = 1.0f;
  int last_word = 0;
};

struct LaneLight {
  int count = 0;
  LaneRead reads[3];
  Color irradiance{0.0f};
};

// What one object's lookup holds fixed over its pixels.
struct GridKernel {
  glm::mat3 linear, normals;
  Vec3 offset, center, minimum;
  float radius = 0.0f, cell = 0.0f;
  int resolution = 0;
  Outside outside = Outside::clamp;
  std::vector<LaneLight> lights;
};

LaneRead lane_read(const StoredValues& values, uint32_t sample, float weight) {
  const SampleBlock block = values.block(sample);
  const uint8_t* end = values.bytes().data() + values.bytes().size();
  return LaneRead{block.bytes, weight, block.scale, static_cast<int>(end - block.bytes) - 4};
}

GridKernel grid_kernel(const GridLayout& layout, const ObjectView& view) {
  GridKernel kernel;
  kernel.linear = view.map.linear;
  kernel.normals = view.map.normals;
  kernel.offset = view.map.offset;
  kernel.center = layout.center();
  kernel.radius = layout.radius();
  kernel.minimum = layout.center() - Vec3(layout.radius());  // GridLayout's minimum_, computed alike
  kernel.cell = layout.cell_size();
  kernel.resolution = layout.resolution();
  kernel.outside = view.outside;
  for (size_t l = 0; l < view.light_count; ++l) {
    const LightReads& reads = view.lights[l].reads;
    LaneLight light;
    light.count = reads.count;
    light.irradiance = view.lights[l].irradiance;
    for (int r = 0; r < reads.count; ++r) light.reads[r] = lane_read(view.values, reads.reads[r].sample, reads.reads[r].weight);
    kernel.lights.push_back(light);
  }
  return kernel;
}

LANES_TARGET inline Lanes splat(int value) { return _mm256_set1_epi32(value); }

// The 4 bytes at byte `offset` of `base` as one integer, little end first, never reading past
// `last_word` + 4: a lane whose word would run past it reads the last whole word and shifts the
// bytes it wanted down (the stored values end exactly where their last value does).
LANES_TARGET inline Lanes gather_word(const uint8_t* base, Lanes offset, Lanes last_word) {
  const Lanes start = _mm256_min_epi32(offset, last_word);
  const Lanes word = _mm256_i32gather_epi32(reinterpret_cast<const int*>(base), start, 1);
  return _mm256_srlv_epi32(word, _mm256_slli_epi32(_mm256_sub_epi32(offset, start), 3));
}

// half_to_float for the two halves of each 32-bit word, by F16C's conversion, exact as half_to_float
// is (it differs only on signalling NaNs, which it quiets; float_to_half never stores one). F16C
// converts four words' halves at a time; the shuffle that parts low halves from high ones leaves the
// lanes in the order [0, 1, 4, 5, 2, 3, 6, 7], so the words are gathered in that order
// (kHalfLaneOrder) and come out in lane order.
constexpr int kHalfLaneOrder = 0xd8;  // _mm256_permute4x64_epi64: 32-bit lanes 0, 1, 4, 5, 2, 3, 6, 7
LANES_TARGET inline void halves_to_floats(Lanes words, V& low_halves, V& high_halves) {
  const V x = _mm256_cvtph_ps(_mm256_castsi256_si128(words)), y = _mm256_cvtph_ps(_mm256_extracti128_si256(words, 1));
  low_halves = _mm256_shuffle_ps(x, y, 0x88);
  high_halves = _mm256_shuffle_ps(x, y, 0xdd);
}

// Lane `low`'s three floats in the low half, lane `low + 4`'s in the high half; the fourth float is
// masked off (never read: the stored values may end with the third).
LANES_TARGET inline V lane_pair(const float* base, const int* index, int low, __m128i three) {
  return _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_maskload_ps(base + index[low], three)),
                              _mm_maskload_ps(base + index[low + 4], three), 1);
}

// StoredDecoding<P, Signed, N>::value for channels 0 .. N-1 of `point` (one per lane) of one read.
template <Precision P, bool Signed, int N>
LANES_TARGET inline void read_point(const LaneRead& read, Lanes point, V (&values)[N]) {
  const Lanes first = _mm256_mullo_epi32(point, splat(N));  // the point's first value
  if constexpr (P == Precision::float32 && N == 3) {
    const float* base = reinterpret_cast<const float*>(read.bytes);
    alignas(32) int index[kWidth];
    _mm256_store_si256(reinterpret_cast<Lanes*>(index), first);
    const __m128i three = _mm_setr_epi32(-1, -1, -1, 0);
    const V a0 = lane_pair(base, index, 0, three), a1 = lane_pair(base, index, 1, three),
            a2 = lane_pair(base, index, 2, three), a3 = lane_pair(base, index, 3, three);
    const V t0 = _mm256_unpacklo_ps(a0, a1), t1 = _mm256_unpacklo_ps(a2, a3), t2 = _mm256_unpackhi_ps(a0, a1),
            t3 = _mm256_unpackhi_ps(a2, a3);
    values[0] = _mm256_shuffle_ps(t0, t1, 0x44);
    values[1] = _mm256_shuffle_ps(t0, t1, 0xee);
    values[2] = _mm256_shuffle_ps(t2, t3, 0x44);
  } else if constexpr (P == Precision::float32) {
    const float* base = reinterpret_cast<const float*>(read.bytes);
#pragma GCC unroll 9
    for (int c = 0; c < N; ++c) values[c] = _mm256_i32gather_ps(base, _mm256_add_epi32(first, splat(c)), 4);
  } else if constexpr (P == Precision::float16) {
    // Words at byte 4w hold channels 2w and 2w + 1; an odd last channel is the high half of the word
    // ending with it, so no word reaches past the point's values.
    const int* base = reinterpret_cast<const int*>(read.bytes);
    const Lanes offset = _mm256_slli_epi32(_mm256_permute4x64_epi64(first, kHalfLaneOrder), 1);
#pragma GCC unroll 4
    for (int w = 0; 2 * w + 1 < N; ++w) {
      const Lanes words = _mm256_i32gather_epi32(base, _mm256_add_epi32(offset, splat(4 * w)), 1);
      halves_to_floats(words, values[2 * w], values[2 * w + 1]);
    }
    if constexpr (N % 2 == 1) {
      const Lanes words = _mm256_i32gather_epi32(base, _mm256_add_epi32(offset, splat(2 * N - 4)), 1);
      V unused;
      halves_to_floats(words, unused, values[N - 1]);
    }
  } else {
    const Lanes last_word = splat(read.last_word);
#pragma GCC unroll 3
    for (int w = 0; 4 * w < N; ++w) {
      const Lanes word = gather_word(read.bytes, _mm256_add_epi32(first, splat(4 * w)), last_word);
#pragma GCC unroll 4
      for (int b = 0; b < 4; ++b) {
        if (4 * w + b >= N) break;
        const Lanes level = Signed ? _mm256_srai_epi32(_mm256_slli_epi32(word, 24 - 8 * b), 24)
                                   : _mm256_and_si256(_mm256_srli_epi32(word, 8 * b), splat(0xff));
        values[4 * w + b] = _mm256_cvtepi32_ps(level);
      }
    }
  }
}

// glm's mat3 x vec3, row `row`: m[0][row] x + m[1][row] y + m[2][row] z, added left to right.
LANES_TARGET inline V transform(const glm::mat3& m, int row, V x, V y, V z) {
  using S = Avx2;
  return S::add(S::add(S::mul(S::set1(m[0][row]), x), S::mul(S::set1(m[1][row]), y)), S::mul(S::set1(m[2][row]), z));
}

// Up to eight receiver points: their pixels (unused lanes repeat the first) and, after the kernel,
// their caustic and whether they have one (`outside: zero` skips points beyond the ball).
struct PixelGroup {
  int count = 0;
  size_t pixels[kWidth];
  alignas(32) float total[3][kWidth];
  int skipped = 0;  // one bit a lane
};

// add_object_caustic_decoded's loop body for the eight lanes of `group`.
template <Precision P, bool Signed, int N>
LANES_TARGET inline void shade_group(const GridKernel& k, const GBuffer& gbuffer, PixelGroup& group) {
  using S = Avx2;
  alignas(32) float lanes[6][kWidth];
  for (int i = 0; i < kWidth; ++i) {
    const size_t pixel = group.pixels[i < group.count ? i : 0];
    const Vec3& p = gbuffer.position[pixel];
    const Vec3& n = gbuffer.normal[pixel];
    lanes[0][i] = p.x, lanes[1][i] = p.y, lanes[2][i] = p.z, lanes[3][i] = n.x, lanes[4][i] = n.y, lanes[5][i] = n.z;
  }
  const V px = S::load(lanes[0]), py = S::load(lanes[1]), pz = S::load(lanes[2]);
  const V nx = S::load(lanes[3]), ny = S::load(lanes[4]), nz = S::load(lanes[5]);
  // point = map.point(position) = linear p + offset; offset from the centre.
  const V ox = S::sub(S::add(transform(k.linear, 0, px, py, pz), S::set1(k.offset.x)), S::set1(k.center.x));
  const V oy = S::sub(S::add(transform(k.linear, 1, px, py, pz), S::set1(k.offset.y)), S::set1(k.center.y));
  const V oz = S::sub(S::add(transform(k.linear, 2, px, py, pz), S::set1(k.offset.z)), S::set1(k.center.z));
  // normal = normalize(normals n) = v x (1 / sqrt(dot(v, v))).
  V mx = transform(k.normals, 0, nx, ny, nz), my = transform(k.normals, 1, nx, ny, nz), mz = transform(k.normals, 2, nx, ny, nz);
  const V inverse = S::div(S::set1(1.0f), S::sqrt(S::add(S::add(S::mul(mx, mx), S::mul(my, my)), S::mul(mz, mz))));
  mx = S::mul(mx, inverse), my = S::mul(my, inverse), mz = S::mul(mz, inverse);
  const V zero = S::set1(0.0f), one = S::set1(1.0f);
  const V distance = S::sqrt(S::add(S::add(S::mul(ox, ox), S::mul(oy, oy)), S::mul(oz, oz)));
  const V radius = S::set1(k.radius);
  const V outside = S::greater(distance, radius);
  const V ratio = S::div(radius, distance);
  group.skipped = k.outside == Outside::zero ? S::lanes(outside) : 0;
  if ((~group.skipped & ((1 << group.count) - 1)) == 0) return;  // every point beyond the ball, none read
  const V fade = k.outside == Outside::fade ? S::select(outside, S::mul(ratio, ratio), one) : one;
  // The value on the ball's surface beyond it.
  const V sx = S::select(outside, S::mul(ox, ratio), ox), sy = S::select(outside, S::mul(oy, ratio), oy),
          sz = S::select(outside, S::mul(oz, ratio), oz);
  // paper_cosine = distance > 0 ? max(0, -dot(normal, point - center) / distance) : 0.
  const V facing = S::add(S::add(S::mul(mx, ox), S::mul(my, oy)), S::mul(mz, oz));
  const V paper_cosine =
      S::bit_and(S::greater(distance, zero), S::max(S::div(S::bit_xor(facing, S::set1(-0.0f)), distance), zero));
  // GridLayout::stencil at center + offset, axis by axis. max() first turns a NaN into 0 (the scalar
  // code's int conversion of a NaN is undefined; this keeps the gathers inside the grid).
  const V last_centre = S::set1(static_cast<float>(k.resolution - 1));
  const V cell = S::set1(k.cell);
  Lanes base[3];
  V fraction[3];
  const V shifted[3] = {sx, sy, sz};
  for (int axis = 0; axis < 3; ++axis) {
    const V position = S::add(S::set1(k.center[axis]), shifted[axis]);
    V local = S::sub(S::div(S::sub(position, S::set1(k.minimum[axis])), cell), S::set1(0.5f));
    local = S::min(S::max(local, zero), last_centre);
    base[axis] = _mm256_min_epi32(_mm256_cvttps_epi32(local), splat(k.resolution - 2));
    fraction[axis] = S::sub(local, _mm256_cvtepi32_ps(base[axis]));
  }
  const V x[2] = {S::sub(one, fraction[0]), fraction[0]}, y[2] = {S::sub(one, fraction[1]), fraction[1]},
          z[2] = {S::sub(one, fraction[2]), fraction[2]};
  const V xy[4] = {S::mul(x[0], y[0]), S::mul(x[1], y[0]), S::mul(x[0], y[1]), S::mul(x[1], y[1])};
  const int row = k.resolution, slice = row * row;
  const Lanes first = _mm256_add_epi32(
      _mm256_mullo_epi32(_mm256_add_epi32(_mm256_mullo_epi32(base[2], splat(row)), base[1]), splat(row)), base[0]);
  const int offsets[4] = {0, 1, row, row + 1};
  V weights[8];
  Lanes points[8];
  for (int corner = 0; corner < 4; ++corner) {
    points[corner] = _mm256_add_epi32(first, splat(offsets[corner]));
    weights[corner] = S::mul(xy[corner], z[0]);
    points[corner + 4] = _mm256_add_epi32(first, splat(slice + offsets[corner]));
    weights[corner + 4] = S::mul(xy[corner], z[1]);
  }
  V total[3] = {zero, zero, zero};
  for (const LaneLight& light : k.lights) {
    V sums[3] = {zero, zero, zero};
    for (int r = 0; r < light.count; ++r) {
      // read_stencil: the stencil's points in order, factor(weight x read weight) x value each.
      const LaneRead& read = light.reads[r];
      V values[N];
#pragma GCC unroll 9
      for (int c = 0; c < N; ++c) values[c] = zero;
#pragma GCC unroll 8
      for (int s = 0; s < 8; ++s) {
        V factor = S::mul(weights[s], S::set1(read.weight));
        if constexpr (P == Precision::uint8) factor = S::mul(factor, S::set1(read.scale));
        V read_values[N];
        read_point<P, Signed, N>(read, points[s], read_values);
#pragma GCC unroll 9
        for (int c = 0; c < N; ++c) values[c] = S::add(values[c], S::mul(factor, read_values[c]));
      }
      // add_shading, read after read.
#pragma GCC unroll 3
      for (int c = 0; c < 3; ++c) {
        if constexpr (N == 3) {
          sums[c] = S::add(sums[c], S::mul(values[c], paper_cosine));
        } else {
          const V dot = S::add(S::add(S::mul(mx, values[3 * c]), S::mul(my, values[3 * c + 1])), S::mul(mz, values[3 * c + 2]));
          sums[c] = S::add(sums[c], dot);
        }
      }
    }
    for (int c = 0; c < 3; ++c) {
      total[c] = S::add(total[c], S::mul(S::mul(S::max(sums[c], zero), S::set1(light.irradiance[c])), fade));
    }
  }
  for (int c = 0; c < 3; ++c) S::store(group.total[c], total[c]);
}

// Shades a full or final group and adds its caustic to the image (before + total, as the scalar code).
template <Precision P, bool Signed, int N>
LANES_TARGET inline void finish_group(const GridKernel& kernel, const GBuffer& gbuffer, PixelGroup& group,
                                           Image& result) {
  shade_group<P, Signed, N>(kernel, gbuffer, group);
  for (int i = 0; i < group.count; ++i) {
    if (group.skipped & (1 << i)) continue;
    const size_t pixel = group.pixels[i];
    const Color before(result.at(pixel, 0), result.at(pixel, 1), result.at(pixel, 2));
    result.set_rgb(pixel, before + Color(group.total[0][i], group.total[1][i], group.total[2][i]));
  }
  group.count = 0;
}

template <Precision P, bool Signed, int N>
LANES_TARGET __attribute__((flatten)) void grid_lanes(const GridKernel& kernel, const GBuffer& gbuffer,
                                                           size_t begin, size_t end, Image& result) {
  PixelGroup group;
  for (size_t pixel = begin; pixel < end; ++pixel) {
    if (!gbuffer.receiver[pixel]) continue;
    group.pixels[group.count++] = pixel;
    if (group.count == kWidth) finish_group<P, Signed, N>(kernel, gbuffer, group, result);
  }
  if (group.count > 0) finish_group<P, Signed, N>(kernel, gbuffer, group, result);
}

template <Precision P, bool Signed, int N>
LANES_TARGET __attribute__((flatten)) void decode_lanes(const StoredValues& values, size_t light_sample,
                                                             float* decoded) {
  const LaneRead read = lane_read(values, static_cast<uint32_t>(light_sample), 1.0f);
  for (size_t point = 0; point < values.points(); point += kWidth) {
    alignas(32) int indices[kWidth];
    for (int i = 0; i < kWidth; ++i) indices[i] = static_cast<int>(std::min(point + i, values.points() - 1));
    V lanes[N];
    read_point<P, Signed, N>(read, _mm256_load_si256(reinterpret_cast<const Lanes*>(indices)), lanes);
    alignas(32) float channel[kWidth];
    for (int c = 0; c < N; ++c) {
      Avx2::store(channel, lanes[c]);
      for (size_t i = 0; i < kWidth && point + i < values.points(); ++i) decoded[(point + i) * N + c] = channel[i];
    }
  }
}

// Calls fn(P, Signed, N) as template arguments for the values' decoding (with_decoding's choice).
template <class Function>
bool with_lane_decoding(const StoredValues& values, Function&& fn) {
  return with_decoding(values, [&]<Precision P, bool Signed, int N>(StoredDecoding<P, Signed, N>) {
    if constexpr (N == 3 || N == 9) {
      fn.template operator()<P, Signed, N>();
      return true;
    } else {
      return false;
    }
  });
}

}  // namespace

bool grid_lanes_apply(const GridLayout& layout, const ObjectView& view) {
  static const bool enabled = lanes_available() && std::getenv("CAUSTICBENCH_LPI_SCALAR_LOOKUP") == nullptr;
  if (!enabled || layout.resolution() < 2) return false;
  const int channels = view.values.channels();
  if (channels != 3 && channels != 9) return false;
  // Gather offsets are 32-bit: a block's byte offsets, and the grid's point numbers times channels.
  if (view.values.bytes().size() < 4 || view.values.bytes().size() > static_cast<size_t>(std::numeric_limits<int>::max()))
    return false;
  for (size_t l = 0; l < view.light_count; ++l) {
    if (!view.lights[l].harmonics.empty()) return false;
    for (int r = 0; r < view.lights[l].reads.count; ++r)
      if (view.lights[l].reads.reads[r].rotated) return false;
  }
  return true;
}

void add_grid_caustic_lanes(const GridLayout& layout, const ObjectView& view, const GBuffer& gbuffer, size_t begin,
                            size_t end, Image& result) {
  const GridKernel kernel = grid_kernel(layout, view);
  with_lane_decoding(view.values, [&]<Precision P, bool Signed, int N>() {
    grid_lanes<P, Signed, N>(kernel, gbuffer, begin, end, result);
  });
}

bool decode_in_lanes(const StoredValues& values, size_t light_sample, std::vector<float>& decoded) {
  if (!lanes_available() || values.bytes().size() < 4) return false;
  decoded.assign(values.points() * static_cast<size_t>(values.channels()), 0.0f);
  return with_lane_decoding(values, [&]<Precision P, bool Signed, int N>() {
    decode_lanes<P, Signed, N>(values, light_sample, decoded.data());
  });
}

}  // namespace causticbench::lpi
