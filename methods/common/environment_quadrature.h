// Environment lights as points on the sphere of directions towards them, each with the irradiance its
// cell brings: what the methods that light with a whole environment integrate against (lpi's hat
// functions and spherical harmonics, PRT's projection). Sums over them are in fixed chunks, so that
// results do not depend on the thread count.
#pragma once

#include <algorithm>
#include <vector>

#include <glm/mat3x3.hpp>

#include "core/light.h"
#include "core/parallel.h"

namespace causticbench {

// Lights that bring light from a spread of directions: an HDR map or the procedural Gaussian spot.
inline bool is_environment_light(LightKind kind) {
  return kind == LightKind::environment_image || kind == LightKind::gaussian_spot;
}

// A posed environment light as points on the sphere of directions towards it (world space), each
// with the radiance there times its cell's solid angle: the irradiance a directional light from that
// cell would bring. Points of zero radiance are left out, so the map's dark parts cost nothing.
struct EnvironmentQuadrature {
  std::vector<Vec3> directions;
  std::vector<glm::dvec3> irradiance;
  glm::dvec3 total() const;
};

// Cells of at most `cell_angle` radians across. An image map: every texel (over which the map is
// constant) cut into n x n equal solid angles, n = ceil(texel size / cell_angle), so the sum is exact
// for the map and converges for smooth weights. The Gaussian spot: rings about its axis out to where
// the radiance beyond holds 1e-6 of its power (5.26 sigma), at most sigma / 8 or cell_angle wide, each
// ring's radial integral by Simpson's rule, cut into azimuth cells of at most cell_angle.
EnvironmentQuadrature environment_quadrature(const LightFrame& light, double cell_angle);

// The cell size that resolves the spherical harmonics of `bands` bands (a sixteenth of pi / bands;
// tested to converge in methods/lpi/tests/test_lpi_environment.cpp).
double harmonic_quadrature_angle(int bands);

// Per coefficient (spherical_harmonics.h order): l_k, the quadrature's irradiance times Y_k of each
// direction taken by `to_build` (then normalised): the map's radiance projected on the basis in that frame.
std::vector<glm::dvec3> harmonic_weights(int bands, const EnvironmentQuadrature& quadrature, const glm::mat3& to_build);

// Sums add(i, sums) over points i into `outputs` sums per chunk of points, then the chunks in order:
// thread-count independent.
template <class AddPoint>
std::vector<glm::dvec3> chunked_sum(size_t points, size_t outputs, AddPoint add) {
  const size_t chunk = 65536;
  const size_t chunks = (points + chunk - 1) / chunk;
  std::vector<std::vector<glm::dvec3>> partial(chunks);
  parallel_blocks(chunks, 1, [&](size_t begin, size_t end, size_t) {
    for (size_t c = begin; c < end; ++c) {
      partial[c].assign(outputs, glm::dvec3(0.0));
      for (size_t i = c * chunk; i < std::min(points, (c + 1) * chunk); ++i) add(i, partial[c]);
    }
  });
  std::vector<glm::dvec3> total(outputs, glm::dvec3(0.0));
  for (const auto& sums : partial)
    for (size_t k = 0; k < outputs; ++k) total[k] += sums[k];
  return total;
}


}  // namespace causticbench
