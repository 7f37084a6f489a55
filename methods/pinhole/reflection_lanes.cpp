// The vectorised geometric parts of pinhole's CPU kernel (declared in reflection_lanes.h).
#include "methods/pinhole/reflection_lanes.h"

#include "methods/common/simd_lanes.h"
#include "methods/pinhole/cube_filter.h"
#include "methods/pinhole/light_map.h"

namespace causticbench {

namespace {

using simd::Avx2;
using simd::Sse;

// The geometric part of the unfiltered reflection for one receiver point and a block of samples: the
// cube-map face and texel coordinates of the direction towards the light (the arithmetic of
// LightCubeMap::direction_to_texel, branch-free) and the weight cos cos A / (d^2 + e), zero where
// either side faces away. GCC 12 does not vectorise the scalar form of this loop by itself.
template <typename S>
__attribute__((always_inline)) inline void reflection_lanes(const ReflectionBlock& b) {
  using V = typename S::Vec;
  const V zero = S::set1(0.0f), one = S::set1(1.0f), half = S::set1(0.5f), two = S::set1(2.0f), sign_bit = S::set1(-0.0f);
  const V xx = S::set1(b.x.x), xy = S::set1(b.x.y), xz = S::set1(b.x.z);
  const V rx = S::set1(b.receiver_normal.x), ry = S::set1(b.receiver_normal.y), rz = S::set1(b.receiver_normal.z);
  const V eps = S::set1(b.epsilon), area = S::set1(b.area), half_resolution = S::set1(0.5f * b.resolution);
  const V last_texel = S::set1(b.resolution - 1.0f), blocks = S::set1(b.occupancy_blocks);
  const V inverse_block = S::set1(1.0f / static_cast<float>(LightCubeMap::kOccupancyBlock));
  for (size_t i = 0; i < b.count; i += S::width) {
    V ox = S::sub(S::load(b.px + i), xx), oy = S::sub(S::load(b.py + i), xy), oz = S::sub(S::load(b.pz + i), xz);
    V distance2 = S::add(S::add(S::mul(ox, ox), S::mul(oy, oy)), S::mul(oz, oz));
    V inverse = S::div(one, S::sqrt(distance2));
    V dx = S::mul(ox, inverse), dy = S::mul(oy, inverse), dz = S::mul(oz, inverse);
    V cos_receiver = S::add(S::add(S::mul(rx, dx), S::mul(ry, dy)), S::mul(rz, dz));
    V snx = S::load(b.nx + i), sny = S::load(b.ny + i), snz = S::load(b.nz + i);
    V cs = S::sub(zero, S::add(S::add(S::mul(snx, dx), S::mul(sny, dy)), S::mul(snz, dz)));
    // Two-sided samples seen from behind: flip the normal (cs becomes -cs; 2 cs n is unchanged).
    V flip = S::bit_and(S::less(cs, zero), S::greater(S::load(b.two_sided + i), half));
    V twice = S::mul(two, cs);
    cs = S::select(flip, S::sub(zero, cs), cs);
    V wx = S::add(dx, S::mul(twice, snx)), wy = S::add(dy, S::mul(twice, sny)), wz = S::add(dz, S::mul(twice, snz));
    V ax = S::and_not(sign_bit, wx), ay = S::and_not(sign_bit, wy), az = S::and_not(sign_bit, wz);
    V x_major = S::bit_and(S::greater_equal(ax, ay), S::greater_equal(ax, az));
    V y_major = S::and_not(x_major, S::greater_equal(ay, az));
    V major = S::select(x_major, ax, S::select(y_major, ay, az));
    V x_positive = S::greater(wx, zero), y_positive = S::greater(wy, zero), z_positive = S::greater(wz, zero);
    V minus_wx = S::sub(zero, wx), minus_wy = S::sub(zero, wy), minus_wz = S::sub(zero, wz);
    V sc = S::select(x_major, S::select(x_positive, minus_wz, wz), S::select(y_major, wx, S::select(z_positive, wx, minus_wx)));
    V tc = S::select(y_major, S::select(y_positive, wz, minus_wz), minus_wy);
    V face = S::select(x_major, S::select(x_positive, zero, one),
                       S::select(y_major, S::select(y_positive, S::set1(2.0f), S::set1(3.0f)),
                                 S::select(z_positive, S::set1(4.0f), S::set1(5.0f))));
    V scale = S::div(half_resolution, major);
    V s_texel = S::add(S::mul(sc, scale), half_resolution), t_texel = S::add(S::mul(tc, scale), half_resolution);
    S::store_int(b.face + i, face);
    S::store(b.texel_s + i, s_texel);
    S::store(b.texel_t + i, t_texel);
    // The occupancy block of the lookup's first texel, as LightCubeMap::lookup_texel computes it.
    V x0 = S::truncate(S::min(S::max(S::sub(s_texel, half), zero), last_texel));
    V y0 = S::truncate(S::min(S::max(S::sub(t_texel, half), zero), last_texel));
    V block_x = S::truncate(S::mul(x0, inverse_block)), block_y = S::truncate(S::mul(y0, inverse_block));
    S::store_int(b.block + i, S::add(S::mul(S::add(S::mul(face, blocks), block_y), blocks), block_x));
    V geometry = b.attenuation ? S::div(S::mul(cs, cos_receiver), S::add(distance2, eps)) : one;
    V facing = S::bit_and(S::greater(cos_receiver, zero), S::greater(cs, zero));
    S::store(b.weight + i, S::bit_and(facing, S::mul(geometry, area)));
    S::store(b.cos_sample + i, cs);
  }
}

void reflection_block_sse(const ReflectionBlock& block) { reflection_lanes<Sse>(block); }
CAUSTICBENCH_AVX2 void reflection_block_avx2(const ReflectionBlock& block) { reflection_lanes<Avx2>(block); }



// The filtered reflection's skip for one receiver point and a block of samples, eight (or four) at a
// time: CubeFilter::may_reach_light's bound from the reflection and its two gradients, with the
// gradients of moved points that face away taken as they come (the exact path takes them as zero,
// which only shrinks its footprint: this bound stays above it), 1 % and 1e-4 rad more for rounding,
// and NaN kept. Only what it keeps goes through the exact scalar lookup, so the sum is bit for bit the
// one without any skip.
template <typename S>
void filtered_skip_lanes(const FilteredSkipBlock& b) {
  using V = typename S::Vec;
  const V zero = S::set1(0.0f), one = S::set1(1.0f), two = S::set1(2.0f), half = S::set1(0.5f);
  const V sign_bit = S::set1(-0.0f);
  const V xx = S::set1(b.x.x), xy = S::set1(b.x.y), xz = S::set1(b.x.z);
  for (size_t i = 0; i < b.count; i += S::width) {
    auto reflection = [&](const float* px, const float* py, const float* pz, const float* nx, const float* ny,
                          const float* nz, V& wx, V& wy, V& wz) {
      V ox = S::sub(S::load(px + i), xx), oy = S::sub(S::load(py + i), xy), oz = S::sub(S::load(pz + i), xz);
      V inverse = S::div(one, S::sqrt(S::add(S::add(S::mul(ox, ox), S::mul(oy, oy)), S::mul(oz, oz))));
      V dx = S::mul(ox, inverse), dy = S::mul(oy, inverse), dz = S::mul(oz, inverse);
      V mx = S::load(nx + i), my = S::load(ny + i), mz = S::load(nz + i);
      V twice = S::mul(two, S::sub(zero, S::add(S::add(S::mul(mx, dx), S::mul(my, dy)), S::mul(mz, dz))));
      wx = S::add(dx, S::mul(twice, mx)), wy = S::add(dy, S::mul(twice, my)), wz = S::add(dz, S::mul(twice, mz));
    };
    V wx, wy, wz, ux, uy, uz, vx, vy, vz;
    reflection(b.px, b.py, b.pz, b.nx, b.ny, b.nz, wx, wy, wz);
    reflection(b.moved[0], b.moved[1], b.moved[2], b.moved[6], b.moved[7], b.moved[8], ux, uy, uz);
    reflection(b.moved[3], b.moved[4], b.moved[5], b.moved[9], b.moved[10], b.moved[11], vx, vy, vz);
    ux = S::sub(ux, wx), uy = S::sub(uy, wy), uz = S::sub(uz, wz);
    vx = S::sub(vx, wx), vy = S::sub(vy, wy), vz = S::sub(vz, wz);
    // The face of w and its axes, as LightCubeMap::direction_to_texel selects them.
    V ax = S::and_not(sign_bit, wx), ay = S::and_not(sign_bit, wy), az = S::and_not(sign_bit, wz);
    V x_major = S::bit_and(S::greater_equal(ax, ay), S::greater_equal(ax, az));
    V y_major = S::and_not(x_major, S::greater_equal(ay, az));
    V x_positive = S::greater(wx, zero), y_positive = S::greater(wy, zero), z_positive = S::greater(wz, zero);
    auto face_s = [&](V a, V, V c) { return S::select(x_major, S::select(x_positive, S::sub(zero, c), c),
                                                      S::select(y_major, a, S::select(z_positive, a, S::sub(zero, a)))); };
    auto face_t = [&](V, V bb, V c) { return S::select(y_major, S::select(y_positive, c, S::sub(zero, c)), S::sub(zero, bb)); };
    auto face_m = [&](V a, V bb, V c) {
      return S::select(x_major, S::select(x_positive, a, S::sub(zero, a)),
                       S::select(y_major, S::select(y_positive, bb, S::sub(zero, bb)), S::select(z_positive, c, S::sub(zero, c))));
    };
    V major = face_m(wx, wy, wz);
    V u = S::div(face_s(wx, wy, wz), major), v = S::div(face_t(wx, wy, wz), major);
    V scale = S::div(S::set1(b.half_resolution), major);
    auto texels = [&](V gx, V gy, V gz) {
      V along = face_m(gx, gy, gz);
      V ds = S::sub(face_s(gx, gy, gz), S::mul(u, along)), dt = S::sub(face_t(gx, gy, gz), S::mul(v, along));
      return S::mul(S::sqrt(S::add(S::mul(ds, ds), S::mul(dt, dt))), scale);
    };
    V length_u = texels(ux, uy, uz), length_v = texels(vx, vy, vz);
    V longer = S::max(length_u, length_v), shorter = S::min(length_u, length_v);
    V width = b.anisotropic ? S::max(S::max(shorter, S::mul(longer, S::set1(1.0f / CubeFilter::kMaxAnisotropy))), one)
                            : S::max(longer, one);
    V reach = S::mul(S::set1(b.support_per_texel), width);
    if (b.anisotropic) {
      V offset = S::mul(half, S::sqrt(S::max(S::add(S::add(S::mul(ux, ux), S::mul(uy, uy)), S::mul(uz, uz)),
                                             S::add(S::add(S::mul(vx, vx), S::mul(vy, vy)), S::mul(vz, vz)))));
      reach = S::add(reach, S::select(S::less(offset, half), S::div(offset, S::sub(one, offset)), S::set1(4.0f)));
    }
    reach = S::add(S::mul(reach, S::set1(1.01f)), S::set1(1e-4f));
    // Skipped only where the bound is a number below pi and every lit cone is beyond it.
    V skip = S::and_not(S::unordered(length_u, length_v), S::less(reach, S::set1(3.0f)));
    for (size_t k = 0; k < b.cone_count; ++k) {
      const float* cone = b.cones + 4 * k;
      V cx = S::sub(wx, S::set1(cone[0])), cy = S::sub(wy, S::set1(cone[1])), cz = S::sub(wz, S::set1(cone[2]));
      V limit = S::add(reach, S::set1(cone[3] + 2e-4f));
      skip = S::bit_and(skip, S::greater(S::add(S::add(S::mul(cx, cx), S::mul(cy, cy)), S::mul(cz, cz)), S::mul(limit, limit)));
    }
    S::store(b.keep + i, S::and_not(skip, one));
  }
}

// Flattened: the lambdas of filtered_skip_lanes must be inlined into the AVX2 function, or they would be
// compiled without AVX2 and pass its vectors in a different way (the psabi warning).
__attribute__((flatten)) void filtered_skip_sse(const FilteredSkipBlock& block) { filtered_skip_lanes<Sse>(block); }
CAUSTICBENCH_AVX2 __attribute__((flatten)) void filtered_skip_avx2(const FilteredSkipBlock& block) {
  filtered_skip_lanes<Avx2>(block);
}


}  // namespace

void reflection_block(const ReflectionBlock& block) {
  simd::has_avx2() ? reflection_block_avx2(block) : reflection_block_sse(block);
}

void filtered_skip(const FilteredSkipBlock& block) { simd::has_avx2() ? filtered_skip_avx2(block) : filtered_skip_sse(block); }

}  // namespace causticbench
