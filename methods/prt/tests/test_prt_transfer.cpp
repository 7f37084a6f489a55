// methods/prt/transfer.h: neighbourhood transfer by photon tracks. A flat mirror under a smooth sky
// stores the mirrored sky (within the band limit, the mirror's finite size and the photons' noise); a
// diffuse object stores nothing (only light after a specular interaction is the caustic's); the
// spherical Fibonacci directions are equal-area; a field is the same for any thread count; the frame's
// product sums alike in AVX2 lanes and in scalar code.
#include <cmath>

#include <glm/gtc/packing.hpp>
#include <gtest/gtest.h>

#include "core/parallel.h"
#include "core/sampling.h"
#include "methods/common/harmonic_lighting.h"
#include "methods/prt/transfer.h"
#include "tests/test_support.h"

namespace causticbench::prt {
namespace {

using causticbench::testing::scene_from_yaml;

// A 4 x 4 mirror at the origin facing up, alone (its own build space).
const char* const kMirror = R"(
camera: {position: [0, 3, 3], look_at: [0, 0, 0], fov_degrees: 50, resolution: [8, 8]}
lights: [{type: directional, direction: [0, -1, 0], irradiance: 1}]
objects:
  - shape: {type: quad, size: [4, 4]}
    material: {type: mirror, reflectance: 0.8}
)";

// The sky L(w) = 1 + w . up (radiance 2 at the zenith, 0 at the nadir): bands 0 and 1 only.
std::vector<double> sky(int bands, const glm::dvec3& up) {
  std::vector<double> coefficients(static_cast<size_t>(coefficient_count(bands)), 0.0);
  coefficients[0] = std::sqrt(4.0 * kPiDouble);
  // w . up = sqrt(4 pi / 3) (up_y Y_1,-1 + up_z Y_10 + up_x Y_11)
  const double k = std::sqrt(4.0 * kPiDouble / 3.0);
  coefficients[1] = k * up.y, coefficients[2] = k * up.z, coefficients[3] = k * up.x;
  return coefficients;
}

TEST(PrtTransfer, FibonacciDirectionsAreUnitAndIntegrateLowBandsClosely) {
  const std::vector<Vec3> directions = fibonacci_directions(400);
  ASSERT_EQ(directions.size(), 400u);
  // The mean of Y_k over equal-area points is the integral over 4 pi: zero for k > 0.
  std::vector<double> mean(16, 0.0);
  for (const Vec3& d : directions) {
    EXPECT_NEAR(glm::length(d), 1.0f, 1e-6f);
    double basis[16];
    evaluate(4, glm::dvec3(d), basis);
    for (int k = 0; k < 16; ++k) mean[k] += basis[k] * 4.0 * kPiDouble / 400.0;
  }
  EXPECT_NEAR(mean[0], std::sqrt(4.0 * kPiDouble), 1e-9);
  for (int k = 1; k < 16; ++k) EXPECT_NEAR(mean[k], 0.0, 2e-2) << "k " << k;
}

// Above the mirror's middle, a receiver facing down sees the mirrored sky: radiance R L(mirror w) from
// below. Its irradiance, within the band limit, is the band-limited clamped-cosine sum of that field,
// which the test projects on a fine quadrature itself. The mirror's edges (2 m away at 0.18 m height:
// under 5 degrees of elevation lost) and the photons' noise (fixed seed) stay within 3 %.
TEST(PrtTransfer, FlatMirrorStoresTheMirroredSky) {
  const Scene scene = scene_from_yaml(kMirror);
  const SceneFrame frame(scene, 0.0);
  TransferSettings settings;
  settings.bands = 4;
  settings.grid_resolution = 16;
  settings.volume_radius = 1.0;
  settings.source_directions = 96;
  settings.photons_per_direction = 40000;
  const TransferField field = precompute_transfer(scene, 0, frame.bounds[0], settings, nullptr);
  const glm::dvec3 up(0.0, 1.0, 0.0);
  const std::vector<double> lighting = sky(settings.bands, up);
  std::vector<float> per_colour;
  for (int c = 0; c < 3; ++c)
    for (double value : lighting) per_colour.push_back(static_cast<float>(value));
  const std::vector<float> incident = incident_field(field, per_colour);
  // The field from below: R (1 + |w_y|) for w_y < 0, zero above; projected on the quadrature.
  const SphereQuadrature quadrature = product_quadrature(kMaxBands);
  std::vector<glm::dvec3> directions;
  std::vector<double> weights, values;
  const int fine = 400;  // a fine midpoint rule in elevation and azimuth: the step at the horizon needs it
  for (int i = 0; i < fine; ++i)
    for (int j = 0; j < 2 * fine; ++j) {
      const double y = -1.0 + (i + 0.5) / fine * 2.0, phi = 2.0 * kPiDouble * (j + 0.5) / (2 * fine);
      const double s = std::sqrt(1.0 - y * y);
      directions.emplace_back(s * std::cos(phi), y, s * std::sin(phi));
      weights.push_back(4.0 * kPiDouble / (2.0 * fine * fine));
      values.push_back(y < 0.0 ? 0.8 * (1.0 - y) : 0.0);
    }
  const std::vector<double> expected_field = project(settings.bands, directions, weights, values);
  const double expected = irradiance_at(settings.bands, expected_field, -up);
  EXPECT_NEAR(expected, 0.8 * 5.0 * kPiDouble / 3.0, 0.05) << "the band limit's own error, small for irradiance";
  for (float x : {-0.5f, 0.0f, 0.5f}) {
    const Vec3 point(x, 0.177f, 0.2f);
    const Color measured = transfer_irradiance(field, incident, point, Vec3(0.0f, -1.0f, 0.0f));
    std::printf("at (%.2f, 0.177, 0.2): %.4f against %.4f (%+.2f %%)\n", x, measured.g, expected,
                100.0 * (measured.g / expected - 1.0));
    EXPECT_NEAR(measured.g, expected, 0.03 * expected);
    EXPECT_FLOAT_EQ(measured.r, measured.g);
    // A receiver facing up there gets nothing of it (the field comes from below), to the band limit.
    const Color facing_up = transfer_irradiance(field, incident, point, Vec3(0.0f, 1.0f, 0.0f));
    EXPECT_NEAR(facing_up.g, irradiance_at(settings.bands, expected_field, up), 0.03 * expected);
  }
}

// Only light after a specular interaction is stored: a diffuse quad's field is zero.
TEST(PrtTransfer, ADiffuseObjectStoresNothing) {
  std::string text = kMirror;
  text.replace(text.find("{type: mirror, reflectance: 0.8}"), std::string("{type: mirror, reflectance: 0.8}").size(),
               "{type: diffuse, albedo: 0.8}");
  const Scene scene = scene_from_yaml(text);
  const SceneFrame frame(scene, 0.0);
  TransferSettings settings;
  settings.bands = 3;
  settings.grid_resolution = 8;
  settings.source_directions = 16;
  settings.photons_per_direction = 2000;
  const TransferField field = precompute_transfer(scene, 0, frame.bounds[0], settings, nullptr);
  EXPECT_GT(field.stats.emitted, 0u);
  for (float value : field.matrices) ASSERT_EQ(value, 0.0f);
}

TEST(PrtTransfer, TheFieldIsTheSameForAnyThreadCount) {
  const Scene scene = scene_from_yaml(kMirror);
  const SceneFrame frame(scene, 0.0);
  TransferSettings settings;
  settings.bands = 3;
  settings.grid_resolution = 8;
  settings.source_directions = 12;
  settings.photons_per_direction = 3000;
  const TransferField many = precompute_transfer(scene, 0, frame.bounds[0], settings, nullptr);
  const TransferField one = [&] {
    const ThreadLimit limit(1);
    return precompute_transfer(scene, 0, frame.bounds[0], settings, nullptr);
  }();
  ASSERT_EQ(many.matrices.size(), one.matrices.size());
  double largest = 0.0;
  for (size_t i = 0; i < one.matrices.size(); ++i) {
    ASSERT_EQ(many.matrices[i], one.matrices[i]) << i;
    largest = std::max(largest, std::abs(static_cast<double>(one.matrices[i])));
  }
  EXPECT_GT(largest, 0.0);
}

// The frame's product sums each row in eight lanes in a fixed order, so the AVX2 lanes (with F16C for half
// floats) and the scalar code every other processor runs give the same bits, for every row length prt
// uses, including those that end inside a lane; and both are the dot product to float rounding.
TEST(PrtTransfer, TheProductsLanesAndScalarCodeSumAlike) {
  if (!__builtin_cpu_supports("avx2") || !__builtin_cpu_supports("f16c")) GTEST_SKIP() << "no AVX2 and F16C here";
  Random random(5, 0);
  for (int bands = 1; bands <= kMaxBands; ++bands) {
    const size_t n = static_cast<size_t>(bands) * bands;
    std::vector<float> row(n), light(n + 8, 0.0f);
    std::vector<uint16_t> halves(n);
    for (int trial = 0; trial < 50; ++trial) {
      double exact = 0.0;
      for (size_t j = 0; j < n; ++j) {
        row[j] = (random.uniform() * 2.0f - 1.0f) * (j % 3 == 0 ? 1e3f : 1e-2f);
        light[j] = (random.uniform() * 2.0f - 1.0f);
        halves[j] = glm::packHalf1x16(row[j] * 1e-3f);
        exact += double(row[j]) * light[j];
      }
      const float scalar = lane_dot(row.data(), light.data(), n, false);
      ASSERT_EQ(scalar, lane_dot(row.data(), light.data(), n, true)) << "bands " << bands << " trial " << trial;
      ASSERT_EQ(lane_dot(halves.data(), light.data(), n, false), lane_dot(halves.data(), light.data(), n, true))
          << "bands " << bands << " trial " << trial;
      EXPECT_NEAR(scalar, exact, 1e-3 * (1.0 + std::abs(exact)));
    }
  }
}

}  // namespace
}  // namespace causticbench::prt
