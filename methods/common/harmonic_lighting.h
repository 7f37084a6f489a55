// Lighting with spherical harmonics (spherical_harmonics.h's basis), as precomputed radiance transfer
// (Sloan, Kautz & Snyder 2002) and lpi's `storage: sh` use it: rotating a function's coefficients, the
// clamped cosine's coefficients that turn radiance into irradiance (Ramamoorthi & Hanrahan 2001), the
// windows that trade a truncated series' ringing for blur, and the truncated delta of a directional
// light.
#pragma once

#include <string>
#include <vector>

#include <glm/mat3x3.hpp>

#include "methods/common/spherical_harmonics.h"

namespace causticbench {

// The rotation of band-limited functions: coefficients of f and of g(d) = f(R^T d) (f turned by R).
// Rotation keeps each band apart, so it is one (2l + 1) x (2l + 1) matrix per band:
//   B_l[m][m'] = integral of Y_lm(R e) Y_lm'(e) de,
// computed on the product quadrature, which integrates these degree-2l polynomials exactly (to rounding).
// Projection rather than a recurrence (Ivanic & Ruedenberg): a few hundred thousand multiply-adds at ten
// bands, once per frame per object, and exact by construction; the tests hold it to 1e-12.
class HarmonicRotation {
 public:
  HarmonicRotation(int bands, const glm::dmat3& rotation);
  int bands() const { return bands_; }
  // The coefficients of the turned function (bands^2 in, bands^2 out).
  std::vector<double> apply(const std::vector<double>& coefficients) const;
  // Band l's matrix, row-major, (2l + 1)^2 values; row m + l, column m' + l.
  const std::vector<double>& band(int l) const { return blocks_[static_cast<size_t>(l)]; }

 private:
  int bands_;
  std::vector<std::vector<double>> blocks_;
};

// Â_l: the clamped cosine max(0, n . w)'s zonal coefficient times sqrt(4 pi / (2l + 1)), so that the
// irradiance of radiance L(w) = sum c_lm Y_lm(w) on a surface of normal n is sum Â_l c_lm Y_lm(n):
// pi, 2 pi / 3, pi / 4, 0, -pi / 24, 0, pi / 64, ... (zero for odd l > 1).
double clamped_cosine(int l);

// sum over k of Â_l(k) coefficients_k Y_k(normal): the irradiance on a surface of unit `normal` under the
// radiance the coefficients describe (directions w towards where the light comes from).
double irradiance_at(int bands, const std::vector<double>& coefficients, const glm::dvec3& normal);

// Windows on a truncated series (beyond Sloan 2002): the factor of band l of n. none: 1. hanning:
// (1 + cos(pi l / n)) / 2. lanczos: sin(x) / x, x = pi l / n. Both are 1 at l = 0, so a window keeps the
// lighting's total (its band 0) and takes from the higher bands the ringing of a sharp light.
enum class HarmonicWindow { none, hanning, lanczos };
HarmonicWindow harmonic_window(const std::string& name);  // none, hanning, lanczos; std::invalid_argument else
double window_factor(HarmonicWindow window, int l, int bands);
// Multiplies each band of `coefficients` by its factor, in place.
void apply_window(HarmonicWindow window, int bands, std::vector<double>& coefficients);

// The truncated delta of a directional light: radiance E delta(w - w_L) has the coefficients E Y_k(w_L),
// w_L the unit direction towards the light.
std::vector<double> directional_coefficients(int bands, const glm::dvec3& towards_light, double irradiance);

}  // namespace causticbench
