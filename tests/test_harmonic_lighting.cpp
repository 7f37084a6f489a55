// methods/common/harmonic_lighting.h: the rotation of spherical-harmonic coefficients against the
// projection of the turned function, the clamped cosine's coefficients against numerical integration,
// the windows, and a directional light's truncated delta against the exact irradiance.
#include <cmath>
#include <cstdio>
#include <vector>

#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>

#include "core/sampling.h"
#include "methods/common/harmonic_lighting.h"
#include "tests/test_support.h"

namespace causticbench {
namespace {

using glm::dvec3;

using causticbench::testing::random_direction;

glm::dmat3 random_rotation(Random& random) {
  return glm::mat3_cast(glm::normalize(glm::dquat(2.0 * random.uniform_double() - 1.0, random_direction(random))));
}

// The coefficients of f(R^T d), by projecting it on the product quadrature (exact for band-limited f).
std::vector<double> projected_turned(int bands, const std::vector<double>& c, const glm::dmat3& rotation) {
  const SphereQuadrature quadrature = product_quadrature(bands);
  std::vector<double> values;
  for (const dvec3& d : quadrature.directions) values.push_back(reconstruct(bands, c, glm::transpose(rotation) * d));
  return project(bands, quadrature.directions, quadrature.weights, values);
}

TEST(HarmonicLighting, RotatedCoefficientsAreTheProjectionOfTheTurnedFunction) {
  Random random(21, 0);
  for (int bands = 1; bands <= kMaxBands; ++bands) {
    std::vector<double> c(static_cast<size_t>(coefficient_count(bands)));
    for (double& value : c) value = 2.0 * random.uniform_double() - 1.0;
    const glm::dmat3 rotation = random_rotation(random);
    const std::vector<double> turned = HarmonicRotation(bands, rotation).apply(c);
    const std::vector<double> expected = projected_turned(bands, c, rotation);
    double change = 0.0;
    for (size_t k = 0; k < c.size(); ++k) {
      ASSERT_NEAR(turned[k], expected[k], 1e-12) << bands << " bands, k " << k;
      change = std::max(change, std::abs(turned[k] - c[k]));
    }
    if (bands > 1) {
      EXPECT_GT(change, 1e-2) << "the rotation moved the coefficients: the check is not vacuous";
    }
    // Turning back restores them; turning by the identity changes nothing.
    const std::vector<double> back = HarmonicRotation(bands, glm::transpose(rotation)).apply(turned);
    const std::vector<double> same = HarmonicRotation(bands, glm::dmat3(1.0)).apply(c);
    for (size_t k = 0; k < c.size(); ++k) {
      ASSERT_NEAR(back[k], c[k], 1e-12);
      ASSERT_NEAR(same[k], c[k], 1e-13);
    }
  }
}

// A point value of the turned function is the original's at the turned-back direction.
TEST(HarmonicLighting, RotationMovesTheFunctionNotTheDirections) {
  Random random(22, 0);
  const int bands = 5;
  std::vector<double> c(static_cast<size_t>(coefficient_count(bands)));
  for (double& value : c) value = 2.0 * random.uniform_double() - 1.0;
  const glm::dmat3 rotation = random_rotation(random);
  const std::vector<double> turned = HarmonicRotation(bands, rotation).apply(c);
  for (int i = 0; i < 50; ++i) {
    const dvec3 d = random_direction(random);
    ASSERT_NEAR(reconstruct(bands, turned, rotation * d), reconstruct(bands, c, d), 1e-12);
  }
}

// Â_l Y_lm(n) is the integral of Y_lm(w) max(0, n . w) over the sphere: checked by a Gauss-Legendre x
// uniform-azimuth rule about n itself (the clamp is then a cut at a node boundary, so the rule is exact
// for the polynomial on each side), against the closed forms' first values.
TEST(HarmonicLighting, ClampedCosineMatchesNumericalIntegration) {
  EXPECT_DOUBLE_EQ(clamped_cosine(0), kPiDouble);
  EXPECT_DOUBLE_EQ(clamped_cosine(1), 2.0 * kPiDouble / 3.0);
  EXPECT_DOUBLE_EQ(clamped_cosine(2), kPiDouble / 4.0);
  EXPECT_DOUBLE_EQ(clamped_cosine(3), 0.0);
  EXPECT_NEAR(clamped_cosine(4), -kPiDouble / 24.0, 1e-15);
  EXPECT_NEAR(clamped_cosine(6), kPiDouble / 64.0, 1e-15);
  Random random(23, 0);
  const int bands = kMaxBands;
  for (int trial = 0; trial < 4; ++trial) {
    const dvec3 n = random_direction(random);
    dvec3 t, b;
    {
      const dvec3 helper = std::abs(n.x) < 0.9 ? dvec3(1, 0, 0) : dvec3(0, 1, 0);
      t = glm::normalize(glm::cross(helper, n));
      b = glm::cross(n, t);
    }
    // Over the hemisphere around n: u = n . w in [0, 1] by Gauss-Legendre (exact to degree 2 * 24 - 1),
    // azimuths uniform.
    const int nodes = 24, azimuths = 48;
    std::vector<double> integral(static_cast<size_t>(coefficient_count(bands)), 0.0), basis(integral.size());
    std::vector<double> abscissas, rule;
    gauss_legendre(nodes, abscissas, rule);
    for (int i = 0; i < nodes; ++i) {
      const double x = abscissas[static_cast<size_t>(i)], weight = rule[static_cast<size_t>(i)];  // on [-1, 1]
      const double u = 0.5 * (x + 1.0), du = 0.5 * weight;
      const double s = std::sqrt(1.0 - u * u);
      for (int j = 0; j < azimuths; ++j) {
        const double phi = 2.0 * kPiDouble * (j + 0.5) / azimuths;
        const dvec3 w = u * n + s * (std::cos(phi) * t + std::sin(phi) * b);
        evaluate(bands, w, basis.data());
        for (size_t k = 0; k < basis.size(); ++k) integral[k] += du * (2.0 * kPiDouble / azimuths) * u * basis[k];
      }
    }
    evaluate(bands, n, basis.data());
    for (int l = 0; l < bands; ++l)
      for (int m = -l; m <= l; ++m) {
        const size_t k = static_cast<size_t>(coefficient_index(l, m));
        ASSERT_NEAR(integral[k], clamped_cosine(l) * basis[k], 1e-12) << "l " << l << " m " << m;
      }
  }
}

// The irradiance of a directional light from its truncated delta approaches E max(0, n . w_L) as bands
// are added: the largest error over the sphere of normals falls (Â_l falls as l^-2.5; the error is
// largest at the terminator, where the clamped cosine has its kink), and a uniform sky of radiance 1
// gives pi on every surface.
TEST(HarmonicLighting, DirectionalLightIrradianceApproachesTheCosine) {
  const dvec3 light = glm::normalize(dvec3(0.3, 0.9, -0.2));
  Random random(24, 0);
  std::vector<dvec3> normals;
  for (int i = 0; i < 2000; ++i) normals.push_back(random_direction(random));
  double previous = 1e9;
  for (int bands : {3, 5, 7, 9}) {
    const std::vector<double> coefficients = directional_coefficients(bands, light, 2.0);
    double largest = 0.0;
    for (const dvec3& n : normals)
      largest = std::max(largest, std::abs(irradiance_at(bands, coefficients, n) - 2.0 * std::max(0.0, glm::dot(n, light))));
    std::printf("%d bands: largest error %.4f of E = 2\n", bands, largest);
    EXPECT_LT(largest, previous) << bands << " bands";
    previous = largest;
  }
  EXPECT_LT(previous, 0.04 * 2.0) << "nine bands (measured 3.4 % of E at the terminator)";
  std::vector<double> sky(static_cast<size_t>(coefficient_count(4)), 0.0);
  sky[0] = std::sqrt(4.0 * kPiDouble);  // radiance 1 everywhere: c_00 = integral of Y_00 = sqrt(4 pi)
  EXPECT_NEAR(irradiance_at(4, sky, glm::normalize(dvec3(1, 2, 3))), kPiDouble, 1e-12);
}

TEST(HarmonicLighting, WindowsKeepBandZeroAndDampTheRest) {
  const int bands = 6;
  for (HarmonicWindow window : {HarmonicWindow::none, HarmonicWindow::hanning, HarmonicWindow::lanczos})
    EXPECT_DOUBLE_EQ(window_factor(window, 0, bands), 1.0);
  EXPECT_NEAR(window_factor(HarmonicWindow::hanning, 3, 6), 0.5, 1e-15);
  EXPECT_NEAR(window_factor(HarmonicWindow::lanczos, 3, 6), 2.0 / kPiDouble, 1e-15);
  EXPECT_NEAR(window_factor(HarmonicWindow::hanning, 6, 6), 0.0, 1e-15);
  std::vector<double> c(static_cast<size_t>(coefficient_count(bands)), 1.0);
  apply_window(HarmonicWindow::hanning, bands, c);
  EXPECT_DOUBLE_EQ(c[0], 1.0);
  for (int l = 1; l < bands; ++l) EXPECT_LT(c[static_cast<size_t>(coefficient_index(l, 0))], c[static_cast<size_t>(coefficient_index(l - 1, 0))]);
  EXPECT_EQ(harmonic_window("lanczos"), HarmonicWindow::lanczos);
  EXPECT_THROW(harmonic_window("hamming"), std::invalid_argument);
}

}  // namespace
}  // namespace causticbench
