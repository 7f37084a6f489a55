// Neighbourhood transfer (Sloan, Kautz & Snyder 2002, Section 7) of one specular object, precomputed by
// photon tracks: on a grid of cells around the object, per cell a matrix M that turns the source
// lighting's spherical-harmonic coefficients L (directions towards the light, in the object's build
// space) into the coefficients l = M L of the caustic radiance arriving in the cell (after at least one
// specular interaction with the object). A receiver of normal n there gets E_c = sum_k Â_l(k) l_k Y_k(n)
// (harmonic_lighting.h's irradiance_at).
//
// The estimator. For each of N source directions w_s (spherical Fibonacci, 4 pi / N each) a parallel
// beam of unit irradiance is shot at the object (photon_tracks.h); a path segment after the first
// specular bounce, of power P and direction of travel w_t, crossing a cell of volume V over a length t,
// adds P t Y_i(-w_t) / V to the cell's incident coefficient i (the track-length estimator of the
// radiance's projection: -w_t is where that light comes from), which is then added to the matrix as
// M_ij += l_i(w_s) Y_j(w_s) 4 pi / N: a Monte Carlo projection of the transport onto both bases at once.
// Sloan et al. ray-traced from each point instead; the estimators agree in expectation.
#pragma once

#include <cstdint>
#include <cstddef>
#include <functional>
#include <memory>
#include <vector>

#include "core/photon_tracer.h"
#include "core/scene.h"
#include "methods/common/grid_layout.h"

namespace causticbench::prt {

struct TransferSettings {
  int bands = 5;                 // sh_order: bands of the basis, n^2 coefficients (the paper's 5: 25)
  int grid_resolution = 32;      // cells a side of the cube around the sampled ball
  double volume_radius = 3.0;    // the ball's radius, in bounding radii of the object
  int source_directions = 256;   // N
  uint64_t photons_per_direction = 20000;
  uint64_t seed = 1;
  bool half = false;             // precision: float16 matrices (half the memory and the frame's reads)
};

// N unit directions of equal area 4 pi / N each on the sphere: the spherical Fibonacci lattice (cos theta
// uniform in the middle of N equal bands, azimuth stepped by the golden angle).
std::vector<Vec3> fibonacci_directions(int count);

// The precomputed field of one object. Per cell, per colour c, per incident coefficient i, the n^2
// values M_ij over source coefficients j, contiguous (what the frame's product l = M L reads in order):
// as floats, or (precision: float16) as IEEE half floats, rounded to nearest from the floats the build
// summed.
struct TransferField {
  int bands = 0;
  std::unique_ptr<GridLayout> grid;
  std::vector<float> matrices;   // cells x 3 x n^2 x n^2 (empty when halves holds them)
  std::vector<uint16_t> halves;  // precision: float16
  size_t stored_values() const { return matrices.empty() ? halves.size() : matrices.size(); }
  size_t stored_bytes() const { return matrices.size() * sizeof(float) + halves.size() * sizeof(uint16_t); }
  // Per source direction (fibonacci_directions order), per colour: the fluence a unit-irradiance beam from it
  // leaves in the grid, sqrt(4 pi) V sum over cells of l_0 (band_limit.h); empty for a build stored before it.
  std::vector<double> direction_response;
  PhotonStats stats;
  double shoot_seconds = 0.0;
  size_t coefficients() const { return static_cast<size_t>(bands) * bands; }
  size_t values_per_cell() const { return 3 * coefficients() * coefficients(); }
  // Floats a cell of the frame's incident field: 3 n^2 rounded up to whole lanes of eight (zeros after).
  size_t incident_stride() const { return (3 * coefficients() + 7) / 8 * 8; }
};

// The grid of a field: the cube around the ball of settings.volume_radius bounding radii.
std::unique_ptr<GridLayout> transfer_grid(const BoundingSphere& bounds, const TransferSettings& settings);

// Shoots every source direction at object `object` of `build_scene` (the object alone, posed in build
// space: build_space.h) and returns its field over a grid centred on `bounds` (the object's bounding
// sphere there). Photon i of direction s draws only from Random(seed, s 2^32 + i), summed in fixed
// chunks: the result does not depend on the thread count. `report(done, total)` after each direction.
TransferField precompute_transfer(const Scene& build_scene, int object, const BoundingSphere& bounds,
                                  const TransferSettings& settings, const std::function<void(size_t, size_t)>& report);

// Replaces the field's floats by half floats (precision: float16).
void store_as_halves(TransferField& field);

// The frame's incident field: per cell, per colour, l = M L (3 x n^2 floats a cell, then zeros to
// incident_stride()), from the lighting L (per colour n^2 coefficients, build space: 3 n^2 floats). Each
// dot product sums in eight lanes in a fixed order (AVX2 where the processor has it, the same order in
// scalar code elsewhere: the same floats either way). Half floats are widened with F16C where the
// processor has it (every one with AVX2), else one by one: the same floats either way.
std::vector<float> incident_field(const TransferField& field, const std::vector<float>& lighting);
// One of its dot products (n <= kMaxBands^2 entries, `light` padded with zeros to whole lanes of eight): in
// AVX2 lanes (`lanes`: the processor must have AVX2 and F16C) or in scalar code. Both give the same bits.
float lane_dot(const float* row, const float* light, size_t n, bool lanes);
float lane_dot(const uint16_t* row, const float* light, size_t n, bool lanes);

// E_c at a build-space point of unit build-space normal, from the frame's incident field: the field's
// coefficients interpolated trilinearly between cell centres (held beyond the outermost), then the
// clamped cosine's sum, negative values (the truncation's ringing) clamped to 0. Zero outside the cube.
Color transfer_irradiance(const TransferField& field, const std::vector<float>& incident, const Vec3& point, const Vec3& normal);

}  // namespace causticbench::prt
