// The vectorised geometric part of csl's CPU evaluation (render knob `lanes: vector` or `float`): for one
// spot light and a tile of up to eight receiver points, four doubles at a time with AVX2 (two with SSE2
// where AVX2 is missing, chosen at run time, methods/common/simd_lanes.h), or with `lanes: float` eight
// floats (four with SSE2), the steps of
// evaluate_spot_light (spot_light_evaluate.h) up to the image lookup: the point in the light's frame,
// the up to four roots of Eqs. 2 and 3 in the same product form, the roots beyond the image dropped and
// a double root kept once, and per root its light plane point, Eq. 4's correction and the receiver's
// cosine. The same operations in the same order as the scalar evaluation; in double its result agrees
// with it to rounding (tested; measured identical), in float to float's rounding amplified where Eq. 4's
// area ratio vanishes (the caustic's fold), as the Vulkan kernel's (tested against the double lanes). The caller looks each ray up in the
// image (csl_render.cpp); points near the axis, where the on-axis treatments apply, go to the scalar
// evaluation whole.
#pragma once

#include <cstddef>
#include <cstdint>

#include "methods/csl/spot_light.h"

namespace causticbench::csl {

constexpr size_t kTilePoints = 8;

// A tile's receiver points in the object's build space, as doubles, structure of arrays. Lanes at and
// beyond `count` are computed but not read.
struct PointTile {
  size_t count = 0;
  double px[kTilePoints], py[kTilePoints], pz[kTilePoints];
  double nx[kTilePoints], ny[kTilePoints], nz[kTilePoints];  // unit normal
  // The distance from the axis below which the on-axis treatment applies: the footprint radius
  // (on_axis: integrate) or axis_epsilon (epsilon).
  double near_axis[kTilePoints];
  // The same in float, what `lanes: float` reads.
  float px_float[kTilePoints], py_float[kTilePoints], pz_float[kTilePoints];
  float nx_float[kTilePoints], ny_float[kTilePoints], nz_float[kTilePoints];
  float near_axis_float[kTilePoints];
};

// The tile of `count` (1 to kTilePoints) points with their unit normals and footprint radii, as
// evaluate_spot_light receives them; the padding lanes repeat the last point.
PointTile make_tile(const Vec3* points, const Vec3* normals, const float* footprints, size_t count,
                    const EvaluationSettings& settings);

// One spot light as the lanes read it.
struct LightLanes {
  double origin[3], axis[3], u[3], v[3];
  double kappa = 0.0, beta = 0.0;
  double max_radius = 0.0;  // the image's: roots beyond it are dropped
  bool intensity_correction = true;
};
LightLanes light_lanes(const SpotGeometry& light, double max_radius, bool intensity_correction);

// Per point, its candidate rays in evaluate_spot_light's order: the two roots of case (i), then the two
// of case (ii).
struct TileRays {
  static constexpr int kCandidates = 4;
  uint32_t near_axis = 0;           // bit i: point i is in front of the light and near its axis
  uint32_t ray[kCandidates] = {};   // bit i: point i has this candidate (a root in (0, max_radius], lit side)
  double x[kCandidates][kTilePoints], y[kCandidates][kTilePoints];  // its light plane point (u, v)
  double correction[kCandidates][kTilePoints], cosine[kCandidates][kTilePoints];
};

// The lanes' precision: double (`lanes: vector`, evaluate_spot_light's operations to rounding) or float
// (`lanes: float`, twice as many lanes; what the Vulkan kernel computes in, to its tolerance). Either
// way the rays are stored as doubles.
enum class LanePrecision { double_precision, single_precision };

void tile_rays(const LightLanes& light, const PointTile& points, TileRays& rays,
               LanePrecision precision = LanePrecision::double_precision);

// The value `spot` (a SpotLight or an InterpolatedSpotLight, reading `image`) adds to value[0..channels)
// at point i of the tile tile_rays made `rays` from: the lookups of its rays, or, where the point is
// near the axis, the scalar evaluation whole at `point`, `normal` and `footprint` (the floats the
// tile's lanes were made from). evaluate_spot_light's value, to rounding.
template <class Spot, class Image>
void tile_value(const Spot& spot, const Image& image, const TileRays& rays, size_t i, const Vec3& point,
                const Vec3& normal, float footprint, const EvaluationSettings& settings, float* value) {
  if ((rays.near_axis >> i) & 1u) {
    spot.evaluate(point, normal, footprint, settings, value);
    return;
  }
  // At most three candidates are rays (on one side the roots' product is negative), as
  // Profile::radii keeps at most three.
  float read[3];
  for (int k = 0; k < TileRays::kCandidates; ++k) {
    if (!((rays.ray[k] >> i) & 1u)) continue;
    if (!image.lookup(rays.x[k][i], rays.y[k][i], read)) continue;  // beyond the light plane's image
    const double correction = rays.correction[k][i], cosine = rays.cosine[k][i];
    for (int c = 0; c < image.channels(); ++c) value[c] += static_cast<float>(read[c] * correction * cosine);
  }
}

}  // namespace causticbench::csl
