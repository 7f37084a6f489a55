// The band limit's lost energy (methods/prt/band_limit.h). Analytic: a response that is the clamped cosine
// about z under a sun from z loses 1 - S_n / S_10 of its fluence at n bands, S_n the clamped cosine's
// series truncated after n bands, sum over l < n of A_l (2 l + 1) / (4 pi) (the zonal coefficients times
// the sun's), for every n and in each colour. On the builds: a glass sphere's response is the same from
// every direction but for the cube's corners (the fluence is power times the path to the cube's side: up to
// sqrt(3) longer towards a corner), so a sun gains or loses little by the band limit; a ring's is not, and
// at 2 bands the counter says so, less at 5; a response resolved to no more than sh_order is unknown.
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "methods/common/harmonic_lighting.h"
#include "methods/prt/band_limit.h"
#include "methods/prt/transfer.h"
#include "tests/test_support.h"

namespace causticbench::prt {
namespace {

double truncated_clamped_cosine(int bands) {
  double sum = 0.0;
  for (int l = 0; l < bands; ++l) sum += clamped_cosine(l) * (2 * l + 1) / (4.0 * kPiDouble);
  return sum;
}

// What the 16384-point Fibonacci quadrature of the response leaves of the closed forms: measured up to
// 8.9e-7 in the change (3 bands) and 6e-7 relative in the full fluence; bounded at about twice that.
// (It was 2e-3, a hundred times the 0.0178 that 5 bands lose.)
constexpr double kQuadratureTolerance = 2e-6;

TEST(PrtBandLimit, AClampedCosineResponseUnderASunLosesItsTruncatedSeries) {
  const int count = 16384;
  const std::vector<Vec3> directions = fibonacci_directions(count);
  const double colour[3] = {1.0, 0.5, 2.0};
  std::vector<double> responses;
  for (const Vec3& direction : directions)
    for (double factor : colour) responses.push_back(factor * std::max(0.0, static_cast<double>(direction.z)));
  const ResponseHarmonics response = response_harmonics(responses);
  ASSERT_EQ(response.bands, kMaxBands);
  const glm::dvec3 up(0.0, 0.0, 1.0);
  const std::vector<double> sun = directional_coefficients(kMaxBands, up, 1.0);
  const std::vector<double> full[3] = {sun, sun, sun};
  for (int bands = 2; bands <= kMaxBands; ++bands) {
    std::vector<float> used;
    const std::vector<double> truncated = directional_coefficients(bands, up, 1.0);
    for (int c = 0; c < 3; ++c)
      for (double value : truncated) used.push_back(static_cast<float>(value));
    const BandLimitEnergy energy = band_limit_energy(response, bands, used, full);
    const double expected = 1.0 - truncated_clamped_cosine(bands) / truncated_clamped_cosine(kMaxBands);
    std::printf("%d bands: change %.5f, expected %.5f (difference %.2e); full %.6f, expected %.6f\n", bands, energy.change(),
                expected, energy.change() - expected, energy.full, 3.5 * truncated_clamped_cosine(kMaxBands));
    EXPECT_NEAR(energy.change(), expected, kQuadratureTolerance) << bands << " bands";
    EXPECT_NEAR(energy.full, 3.5 * truncated_clamped_cosine(kMaxBands), kQuadratureTolerance * energy.full) << bands << " bands";
  }
}

// The record's change of the first object's fluence (signed: negative is a gain), or NaN when unknown.
double band_limit_change(const std::string& scene_text, const std::vector<std::string>& knobs) {
  const FrameResult result = causticbench::testing::render(causticbench::testing::scene_from_yaml(scene_text), "prt", knobs);
  const nlohmann::json& record = result.method_record;
  if (record.at("lost_to_band_limit").is_null()) return std::nan("");
  EXPECT_EQ(record.at("lost_to_band_limit").get<double>(),
            std::max(0.0, record.at("objects")[0].at("band_limit").at("change").get<double>()));
  return record.at("objects")[0].at("band_limit").at("change").get<double>();
}

const char* const kRingUnderASun = R"(
camera: {type: orthographic, position: [0, 5, 0.3], look_at: [0, 0, 0.3], up: [0, 0, 1], view_height: 4.4, resolution: [32, 32]}
lights: [{type: directional, direction: [0.0, -0.5, 0.8660254], irradiance: 3.0}]
objects:
  - shape: {type: quad, size: [8, 8]}
    material: {type: diffuse, albedo: 0.75}
  - shape: {type: ring, radius: 1.0, height: 0.5}
    material: {type: mirror, reflectance: 0.9}
)";

TEST(PrtBandLimit, ASphereLosesNothingToTheBandLimitAndARingDoes) {
  const std::vector<std::string> build = {"grid_resolution=12", "volume_radius=3", "source_directions=200",
                                          "photons_per_direction=4000"};
  std::vector<std::string> two = build, five = build;
  two.push_back("sh_order=2");
  five.push_back("sh_order=5");
  const double sphere_two = band_limit_change(causticbench::testing::kSmallGlassSphere, two);
  const double sphere_five = band_limit_change(causticbench::testing::kSmallGlassSphere, five);
  const double ring_two = band_limit_change(kRingUnderASun, two), ring_five = band_limit_change(kRingUnderASun, five);
  std::printf("fluence change by the band limit under a sun: glass sphere %.4f / %.4f, ring %.4f / %.4f (2 / 5 bands)\n",
              sphere_two, sphere_five, ring_two, ring_five);
  EXPECT_LT(std::abs(sphere_two), 0.05);
  EXPECT_LT(std::abs(sphere_five), 0.01);
  EXPECT_GT(ring_two, 0.1);
  EXPECT_LT(std::abs(ring_five), 0.5 * ring_two);
  // 60 directions resolve the response to 5 bands: nothing beyond sh_order 5 to compare with.
  std::vector<std::string> few = {"grid_resolution=12", "volume_radius=3", "source_directions=60",
                                  "photons_per_direction=2000", "sh_order=5"};
  EXPECT_TRUE(std::isnan(band_limit_change(kRingUnderASun, few)));
}

}  // namespace
}  // namespace causticbench::prt
