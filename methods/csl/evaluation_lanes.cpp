// The vectorised geometric part of csl's CPU evaluation (declared in evaluation_lanes.h). Each line
// mirrors a line of evaluate_spot_light and of Profile (spot_light_evaluate.h, spot_light.cpp),
// including glm's order of summation in dot products ((x + y) + z) and normalize (v times 1 / sqrt).
#include "methods/csl/evaluation_lanes.h"

#include <algorithm>

#include "methods/common/simd_lanes.h"

namespace causticbench::csl {

LightLanes light_lanes(const SpotGeometry& light, double max_radius, bool intensity_correction) {
  LightLanes lanes;
  for (int k = 0; k < 3; ++k) {
    lanes.origin[k] = light.origin[k];
    lanes.axis[k] = light.axis[k];
    lanes.u[k] = light.u[k];
    lanes.v[k] = light.v[k];
  }
  lanes.kappa = light.profile.kappa;
  lanes.beta = light.profile.beta;
  lanes.max_radius = max_radius;
  lanes.intensity_correction = intensity_correction;
  return lanes;
}

PointTile make_tile(const Vec3* points, const Vec3* normals, const float* footprints, size_t count,
                    const EvaluationSettings& settings) {
  PointTile tile;
  tile.count = count;
  for (size_t j = 0; j < kTilePoints; ++j) {
    const size_t from = std::min(j, count - 1);
    tile.px[j] = points[from].x, tile.py[j] = points[from].y, tile.pz[j] = points[from].z;
    tile.nx[j] = normals[from].x, tile.ny[j] = normals[from].y, tile.nz[j] = normals[from].z;
    tile.near_axis[j] = settings.on_axis == OnAxis::epsilon ? settings.axis_epsilon : footprints[from];
    tile.px_float[j] = points[from].x, tile.py_float[j] = points[from].y, tile.pz_float[j] = points[from].z;
    tile.nx_float[j] = normals[from].x, tile.ny_float[j] = normals[from].y, tile.nz_float[j] = normals[from].z;
    tile.near_axis_float[j] = static_cast<float>(tile.near_axis[j]);
  }
  return tile;
}

namespace {

// (x0 x1 + y0 y1) + z0 z1, glm's order. Functions, not lambdas: a lambda is compiled without AVX2 and
// cannot inline the AVX2 operations.
template <typename S>
__attribute__((always_inline)) inline typename S::Vec dot3(typename S::Vec x0, typename S::Vec y0, typename S::Vec z0,
                                                           typename S::Vec x1, typename S::Vec y1, typename S::Vec z1) {
  return S::add(S::add(S::mul(x0, x1), S::mul(y0, y1)), S::mul(z0, z1));
}

// The tile's arrays in the lanes' precision.
template <typename T>
struct TileArrays {
  const T *px, *py, *pz, *nx, *ny, *nz, *near_axis;
};
inline TileArrays<double> tile_arrays(const PointTile& p, double) {
  return {p.px, p.py, p.pz, p.nx, p.ny, p.nz, p.near_axis};
}
inline TileArrays<float> tile_arrays(const PointTile& p, float) {
  return {p.px_float, p.py_float, p.pz_float, p.nx_float, p.ny_float, p.nz_float, p.near_axis_float};
}

template <typename S>
__attribute__((always_inline)) inline void tile_rays_lanes(const LightLanes& l, const PointTile& tile, TileRays& out) {
  using V = typename S::Vec;
  using Scalar = typename S::Scalar;
  const TileArrays<Scalar> p = tile_arrays(tile, Scalar());
  const V zero = S::set1(0.0), one = S::set1(1.0), sign_bit = S::set1(-0.0);
  const V ox = S::set1(l.origin[0]), oy = S::set1(l.origin[1]), oz = S::set1(l.origin[2]);
  const V ax = S::set1(l.axis[0]), ay = S::set1(l.axis[1]), az = S::set1(l.axis[2]);
  const V ux = S::set1(l.u[0]), uy = S::set1(l.u[1]), uz = S::set1(l.u[2]);
  const V vx = S::set1(l.v[0]), vy = S::set1(l.v[1]), vz = S::set1(l.v[2]);
  const V kappa = S::set1(l.kappa), beta = S::set1(l.beta), max_radius = S::set1(l.max_radius);
  out.near_axis = 0;
  for (int k = 0; k < TileRays::kCandidates; ++k) out.ray[k] = 0;
  for (size_t i = 0; i < kTilePoints; i += S::width) {
    // Into the light's frame.
    const V dx = S::sub(S::load(p.px + i), ox), dy = S::sub(S::load(p.py + i), oy), dz = S::sub(S::load(p.pz + i), oz);
    const V z = dot3<S>(dx, dy, dz, ax, ay, az);
    const V cx = S::sub(dx, S::mul(z, ax)), cy = S::sub(dy, S::mul(z, ay)), cz = S::sub(dz, S::mul(z, az));
    const V rho = S::sqrt(dot3<S>(cx, cy, cz, cx, cy, cz));
    const V in_front = S::greater(z, zero);
    const V near = S::bit_and(in_front, S::less(rho, S::load(p.near_axis + i)));
    const V regular = S::bit_and(S::and_not(near, in_front), S::greater(rho, zero));
    out.near_axis |= static_cast<uint32_t>(S::lanes(near)) << i;
    if (S::lanes(regular) == 0) continue;
    const V wx = S::div(cx, rho), wy = S::div(cy, rho), wz = S::div(cz, rho);  // outward
    const V nx = S::load(p.nx + i), ny = S::load(p.ny + i), nz = S::load(p.nz + i);
    // Profile::radii: s(r) = -A r^2 - B r = +rho, then -rho.
    const V z_kappa = S::mul(z, kappa);
    const V a = S::mul(z_kappa, beta), b = S::sub(z_kappa, one);
    const V linear = S::equal(a, zero);
    // ds(r, z)'s constant part, 1 - z kappa, and its slope's factor 2 z kappa beta.
    const V ds_constant = S::sub(one, z_kappa), ds_slope = S::mul(S::mul(S::mul(S::set1(2.0), z), kappa), beta);
    for (int side = 0; side < 2; ++side) {
      const V c = side == 0 ? rho : S::bit_xor(sign_bit, rho);
      // positive_roots: the product form q = -(b + sign(b) sqrt(b^2 - 4ac)) / 2, roots q / a and c / q;
      // a = 0: the one root -c / b. A negative discriminant gives NaN roots, q = 0 a zero and an
      // infinite one: all dropped by the range test below, as the scalar form drops them.
      const V discriminant = S::sub(S::mul(b, b), S::mul(S::mul(S::set1(4.0), a), c));
      const V root = S::sqrt(discriminant);
      const V q = S::mul(S::set1(-0.5), S::add(b, S::bit_or(S::and_not(sign_bit, root), S::bit_and(sign_bit, b))));
      const V first = S::select(linear, S::div(S::bit_xor(sign_bit, c), b), S::div(q, a)), second = S::div(c, q);
      const V side_sign = side == 0 ? one : S::bit_xor(sign_bit, one);
      for (int which = 0; which < 2; ++which) {
        const V r = which == 0 ? first : second;
        V keep = S::bit_and(regular, S::bit_and(S::greater(r, zero), S::less_equal(r, max_radius)));
        if (which == 1) keep = S::and_not(S::equal(second, first), keep);  // a double root, once
        if (S::lanes(keep) == 0) continue;
        // The ray's light plane point p - c, and its (u, v) coordinates.
        const V signed_r = S::mul(side_sign, r);
        const V fx = S::mul(signed_r, wx), fy = S::mul(signed_r, wy), fz = S::mul(signed_r, wz);
        const int k = 2 * side + which;
        S::store_double(out.x[k] + i, dot3<S>(fx, fy, fz, ux, uy, uz));
        S::store_double(out.y[k] + i, dot3<S>(fx, fy, fz, vx, vy, vz));
        // Eq. 4's area ratio |(1 - z g(r)) ds(r, z)|, bounded below by 1e-6.
        const V g = S::mul(kappa, S::add(one, S::mul(beta, r)));
        const V ratio = S::and_not(sign_bit, S::mul(S::sub(one, S::mul(z, g)), S::sub(ds_constant, S::mul(ds_slope, r))));
        S::store_double(out.correction[k] + i, l.intensity_correction ? S::div(one, S::max(ratio, S::set1(1e-6))) : one);
        // The ray's direction and the receiver's |n.e| / |a.e|.
        V ex = S::sub(ax, S::mul(g, fx)), ey = S::sub(ay, S::mul(g, fy)), ez = S::sub(az, S::mul(g, fz));
        const V inverse = S::div(one, S::sqrt(dot3<S>(ex, ey, ez, ex, ey, ez)));
        ex = S::mul(ex, inverse), ey = S::mul(ey, inverse), ez = S::mul(ez, inverse);
        const V cosine = S::div(S::max(S::bit_xor(sign_bit, dot3<S>(nx, ny, nz, ex, ey, ez)), zero), dot3<S>(ax, ay, az, ex, ey, ez));
        S::store_double(out.cosine[k] + i, cosine);
        keep = S::and_not(S::less_equal(cosine, zero), keep);
        out.ray[k] |= static_cast<uint32_t>(S::lanes(keep)) << i;
      }
    }
  }
}

void tile_rays_sse(const LightLanes& light, const PointTile& points, TileRays& rays) {
  tile_rays_lanes<simd::SseDouble>(light, points, rays);
}
void tile_rays_sse_float(const LightLanes& light, const PointTile& points, TileRays& rays) {
  tile_rays_lanes<simd::Sse>(light, points, rays);
}
// Flattened: every helper is inlined into the AVX2 function, so that no AVX vector crosses a call.
CAUSTICBENCH_AVX2 __attribute__((flatten)) void tile_rays_avx2(const LightLanes& light, const PointTile& points,
                                                              TileRays& rays) {
  tile_rays_lanes<simd::Avx2Double>(light, points, rays);
}
CAUSTICBENCH_AVX2 __attribute__((flatten)) void tile_rays_avx2_float(const LightLanes& light, const PointTile& points,
                                                                    TileRays& rays) {
  tile_rays_lanes<simd::Avx2>(light, points, rays);
}

}  // namespace

void tile_rays(const LightLanes& light, const PointTile& points, TileRays& rays, LanePrecision precision) {
  if (precision == LanePrecision::single_precision) {
    simd::has_avx2() ? tile_rays_avx2_float(light, points, rays) : tile_rays_sse_float(light, points, rays);
  } else {
    simd::has_avx2() ? tile_rays_avx2(light, points, rays) : tile_rays_sse(light, points, rays);
  }
}

}  // namespace causticbench::csl
