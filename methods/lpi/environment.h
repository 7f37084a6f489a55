// Environment lights in lpi (beyond Wyman 2003: Liu 2008, Table 1, says LPI cannot render them). A
// light sample's volume holds caustic irradiance per unit irradiance of a directional light from its
// direction; light from a whole sphere of directions is the sum over light samples of each volume
// times the irradiance the map brings from that sample's cell of the sphere:
//   E_c(x) = sum_s W_s V_s(x),   W_s = integral over the sphere of L(w) h_s(w) dw,
// where h_s is the sample's barycentric hat function: its weight in the blend of a directional light
// from w (the gnomonic barycentric weight in the spherical triangle containing w, zero outside the
// triangles around it). The hats sum to one everywhere, so the W_s sum to the map's whole integral,
// and E_c is exactly the integral over the map of what the barycentric blend renders for each single
// direction (before the clamp of the receiver's shading). With `storage: sh` the same integral is a
// dot product, as precomputed radiance transfer does it: V(w, x) = sum_k c_k(x) Y_k(w), so
// E_c(x) = sum_k c_k(x) l_k with l_k = integral of L(w) Y_k(w) dw, w the direction TOWARDS the light
// in both (the samples are directions towards the light; a photon of the map's radiance arriving
// from w travels along -w).
//
// The integrals are sums over a quadrature of the map in world space (environment_quadrature), each
// point's direction turned into the object's build space as a directional light's is. Per frame the
// weights combine the stored blocks into one volume (combine_blocks), so a pixel reads one stencil
// whatever the number of light samples.
#pragma once

#include <vector>

#include <glm/mat3x3.hpp>

#include "core/light.h"
#include "methods/common/environment_quadrature.h"
#include "methods/common/geodesic.h"
#include "methods/common/stored_values.h"

namespace causticbench::lpi {

// The cell size that resolves a set's hat functions (an eighth of its longest edge); the harmonics' is
// harmonic_quadrature_angle (methods/common/environment_quadrature.h). Tested to converge: a weight is
// then within about 5e-3 of its own value, 5e-4 of the map's total (methods/lpi/tests/test_lpi_environment.cpp).
// Real maps' texels are mostly finer than that already (the forest's 0.35 degrees): one point each.
double hat_quadrature_angle(const SphericalMesh& mesh);

// Per point of `mesh`: W_s, the quadrature's irradiance times the point's hat function, each
// direction taken into build space by `to_build` (then normalised, as a directional light's).
// Summed in fixed chunks in order: the same result for any thread count.
std::vector<glm::dvec3> hat_weights(const SphericalMesh& mesh, const EnvironmentQuadrature& quadrature,
                                    const glm::mat3& to_build);

// One block of float32 values: the sum over blocks b of weights[b] (per colour channel) times block
// b. Blocks of zero weight are skipped. Paper orientation: channel c is colour c; vector: channels
// 3c .. 3c+2 are colour c's vector.
StoredValues combine_blocks(const StoredValues& values, const std::vector<glm::dvec3>& weights);

}  // namespace causticbench::lpi
