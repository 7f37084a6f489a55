// Real spherical harmonics for lpi's compressed storage (Wyman et al. 2003, Section 4.3 and Figure 9:
// irradiance per cell over the sphere of light directions, or per shell over its directions, as a few
// coefficients). `bands` is the number of bands n (degrees l = 0 .. n-1, n^2 coefficients); we read
// the paper's "5th order spherical harmonic" as 5 bands, 25 coefficients.
//
// Convention: orthonormal over the sphere (the integral of Y_k Y_k' over all directions is 1 when
// k == k', else 0), polar axis z, no Condon-Shortley phase. With K_lm = sqrt((2l+1)/(4 pi) (l-m)!/(l+m)!)
// and P_l^m(z) = (1 - z^2)^(m/2) d^m/dz^m P_l(z) (positive for m <= l near the pole):
//   Y_l0 = K_l0 P_l(z),  Y_lm = sqrt(2) K_lm P_l^m(z) cos(m phi),  Y_l,-m = sqrt(2) K_lm P_l^m(z) sin(m phi)
// for m > 0, so that Y_1,-1 = c y, Y_10 = c z, Y_11 = c x with c = sqrt(3 / (4 pi)). Coefficient k holds
// (l, m) at k = l*l + l + m, m = -l .. l.
#pragma once

#include <vector>

#include <glm/vec3.hpp>

#include "core/math.h"

namespace causticbench {

inline constexpr int kMaxBands = 10;

// bands^2; std::invalid_argument unless 1 <= bands <= kMaxBands (as for every function here).
int coefficient_count(int bands);
inline int coefficient_index(int l, int m) { return l * l + l + m; }

// All bands^2 basis values at a unit direction into out[0 .. bands^2): polynomials in its Cartesian
// components (an associated Legendre recurrence in z times the real and imaginary parts of
// (x + i y)^m), so no trigonometry and no division. The direction is not normalised here.
void evaluate(int bands, const Vec3& unit_direction, float* out);
void evaluate(int bands, const glm::dvec3& unit_direction, double* out);
// The float factors evaluate() recurs with, for a kernel that repeats it (prt's lookup.comp): per
// coefficient k < bands^2, the scale, then the recurrence's two factors (3 bands^2 floats, scale first;
// 0 where evaluate() reads none).
std::vector<float> basis_factors(int bands);

// The Gauss-Legendre rule of `nodes` nodes on [-1, 1] (exact for polynomials of degree 2 nodes - 1):
// its abscissas, descending, and weights (summing to 2), by Newton's iteration on P_nodes.
void gauss_legendre(int nodes, std::vector<double>& abscissas, std::vector<double>& weights);

// Integrates polynomials on the sphere of degree up to 2 bands exactly (so every product of two basis
// functions): Gauss-Legendre in cos(theta) with bands + 1 nodes times 2 bands + 1 uniform azimuths.
// The weights sum to 4 pi. Double precision throughout, so that the tests can hold it to 1e-10.
struct SphereQuadrature {
  std::vector<glm::dvec3> directions;
  std::vector<double> weights;
};
SphereQuadrature product_quadrature(int bands);

// c_k = sum_i weights_i values_i Y_k(directions_i): with a quadrature's weights, the projection onto
// the basis; with photon weights, its Monte Carlo estimate. The three lists must be equally long.
std::vector<double> project(int bands, const std::vector<glm::dvec3>& directions, const std::vector<double>& weights,
                            const std::vector<double>& values);
std::vector<double> project(int bands, const std::vector<Vec3>& directions, const std::vector<double>& weights,
                            const std::vector<double>& values);

// sum_k coefficients_k Y_k(d); coefficients must hold bands^2 values.
double reconstruct(int bands, const std::vector<double>& coefficients, const glm::dvec3& unit_direction);
double reconstruct(int bands, const std::vector<double>& coefficients, const Vec3& unit_direction);

// Per degree l, sum over m of c_lm^2: invariant under rotations of the function.
std::vector<double> band_energies(int bands, const std::vector<double>& coefficients);

}  // namespace causticbench
