// lpi under environment lights (methods/lpi/environment.h; beyond Wyman 2003): the map's weights on
// the light samples (conservation, convergence of the quadrature, the texel directions the reference
// reads), a tiny bright patch against the directional light it approximates (both the hat-function
// sum and the spherical-harmonic dot product, which checks the direction convention), the dot product
// against the sample sum on a smooth map, the samples `light_samples: auto` keeps, the refusals, and
// the reference on a small scene.
#include <cmath>
#include <cstdio>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "core/errors.h"
#include "core/image.h"
#include "core/image_statistics.h"
#include "core/light.h"
#include "methods/lpi/environment.h"
#include "methods/lpi/harmonic_storage.h"
#include "methods/lpi/light_samples.h"
#include "methods/common/spherical_harmonics.h"
#include "tests/test_support.h"

using namespace causticbench;
using causticbench::testing::kSmallGlassSphere;
using causticbench::testing::replace_once;
using causticbench::testing::scene_from_yaml;

namespace {

const char* const kSphereLight = "{type: directional, direction: [0.3, -1, 0.2], irradiance: 1}";

// A lat-long map of width x height texels, radiance(direction at the texel's centre) per texel.
template <class Radiance>
std::string write_map(const causticbench::testing::TemporaryFolder& folder, const std::string& name, int width, int height,
                      Radiance radiance) {
  Image map(width, height, 3);
  for (int y = 0; y < height; ++y) {
    const double theta = kPiDouble * (y + 0.5) / height;
    for (int x = 0; x < width; ++x) {
      const double phi = 2.0 * kPiDouble * (x + 0.5) / width;
      const Vec3 direction(static_cast<float>(std::sin(theta) * std::cos(phi)), static_cast<float>(std::cos(theta)),
                           static_cast<float>(std::sin(theta) * std::sin(phi)));
      const Color value = radiance(direction);
      for (int c = 0; c < 3; ++c) map.at(static_cast<size_t>(y) * width + x, c) = value[c];
    }
  }
  const std::string path = folder.path(name);
  write_exr(map, path);
  return path;
}

Light map_light(const std::string& path, double rotation_degrees = 0.0) {
  Light light;
  light.kind = LightKind::environment_image;
  light.name = "map";
  light.image_path = path;
  light.environment = std::make_shared<EnvironmentMap>(path, 1.0, rotation_degrees);
  return light;
}

Light spot_light(const glm::dvec3& travel, double solid_angle, const Color& irradiance) {
  Light light;
  light.kind = LightKind::gaussian_spot;
  light.name = "spot";
  light.direction = Vec3Track::constant(travel);
  light.irradiance = irradiance;
  light.solid_angle = solid_angle;
  return light;
}

glm::mat3 turn() { return lpi::rotation_between(glm::normalize(Vec3(0.2f, 1.0f, -0.4f)), glm::normalize(Vec3(1.0f, 0.3f, 0.5f))); }

double largest(const Image& image) {
  double value = 0.0;
  for (float v : image.values()) value = std::max(value, static_cast<double>(v));
  return value;
}

double largest_difference(const Image& a, const Image& b) {
  double value = 0.0;
  for (size_t i = 0; i < a.values().size(); ++i)
    value = std::max(value, std::fabs(static_cast<double>(a.values()[i]) - b.values()[i]));
  return value;
}

}  // namespace

// The quadrature reads each texel in the direction the map itself looks it up (EnvironmentMap::radiance,
// what the reference and pinhole read), rotation included.
TEST(LpiEnvironment, TexelDirectionsReadTheirOwnTexels) {
  causticbench::testing::TemporaryFolder folder("lpi_environment_texels");
  int counter = 0;
  const std::string path = write_map(folder, "ramp.exr", 16, 8, [&](const Vec3&) { return Color(static_cast<float>(++counter)); });
  for (double rotation : {0.0, 37.0, -120.0}) {
    const EnvironmentMap map(path, 1.0, rotation);
    for (int y = 0; y < map.height(); ++y)
      for (int x = 0; x < map.width(); ++x)
        for (double s : {0.1, 0.5, 0.9}) {
          ASSERT_EQ(map.radiance(map.texel_direction(x, y, s, 1.0 - s)), map.texel(x, y)) << x << " " << y << " " << rotation;
        }
  }
}

// Conservation: the hat functions sum to one everywhere, so a uniform map of radiance L gives weights
// summing to 4 pi L over any set, turned or not (to rounding). By the icosahedron's symmetry the 12
// vertices of level 0 share it equally: to the quadrature's error at the chosen cells (measured
// 2.2e-3 and 2.9e-3 of a share, unturned and turned), which cells a quarter the size cut below 5e-4
// (measured 1.5e-4 and 1.9e-4). The harmonic weights of a uniform map are L sqrt(4 pi) on Y_00 and 0
// elsewhere (measured within 2.6e-4 of l_00).
TEST(LpiEnvironment, UniformMapWeightsSumToFourPiL) {
  causticbench::testing::TemporaryFolder folder("lpi_environment_uniform");
  const Color radiance(0.5f, 1.0f, 2.0f);
  const Light light = map_light(write_map(folder, "uniform.exr", 24, 12, [&](const Vec3&) { return radiance; }), 20.0);
  const LightFrame posed = pose_light(light, 0.0);
  for (const glm::mat3& to_build : {glm::mat3(1.0f), turn()}) {
    for (const auto& [level, at] : {std::pair{0, lpi::SampleAt::vertices}, std::pair{2, lpi::SampleAt::vertices},
                                    std::pair{1, lpi::SampleAt::faces}}) {
      const lpi::LightSampleSet set = lpi::geodesic_samples(level, at);
      const EnvironmentQuadrature quadrature = environment_quadrature(posed, lpi::hat_quadrature_angle(*set.mesh));
      const std::vector<glm::dvec3> weights = lpi::hat_weights(*set.mesh, quadrature, to_build);
      glm::dvec3 sum(0.0);
      for (const glm::dvec3& w : weights) sum += w;
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(sum[c], 4.0 * kPiDouble * radiance[c], 1e-6 * 4.0 * kPiDouble * radiance[c]);
      if (level == 0 && at == lpi::SampleAt::vertices) {
        const double share = 4.0 * kPiDouble / 12.0;
        const std::vector<glm::dvec3> finer = lpi::hat_weights(
            *set.mesh, environment_quadrature(posed, lpi::hat_quadrature_angle(*set.mesh) / 4.0), to_build);
        double error = 0.0, finer_error = 0.0;
        for (size_t s = 0; s < weights.size(); ++s) {
          error = std::max(error, std::fabs(weights[s].y - share) / share);
          finer_error = std::max(finer_error, std::fabs(finer[s].y - share) / share);
        }
        std::printf("level-0 shares of a uniform map: largest error %.2e, with cells a quarter the size %.2e\n", error,
                    finer_error);
        EXPECT_LT(error, 5e-3);
        EXPECT_LT(finer_error, 5e-4);
      }
    }
    const EnvironmentQuadrature quadrature = environment_quadrature(posed, harmonic_quadrature_angle(5));
    const std::vector<glm::dvec3> harmonics = harmonic_weights(5, quadrature, to_build);
    const double l00 = radiance.g * std::sqrt(4.0 * kPiDouble);
    EXPECT_NEAR(harmonics[0].y, l00, 1e-6 * l00);
    double off = 0.0;
    for (size_t k = 1; k < harmonics.size(); ++k) off = std::max(off, std::fabs(harmonics[k].y) / l00);
    std::printf("uniform map: largest harmonic weight beyond Y_00 %.2e of l_00\n", off);
    EXPECT_LT(off, 5e-4);
  }
}

// The quadrature's cell size (an eighth of the longest edge of the set) is converged: halving it
// twice moves no weight by more than 2e-3 of the map's total, for a map with sharp texel edges and
// for the Gaussian spot, and the change shrinks as the cells do.
TEST(LpiEnvironment, WeightsConvergeWithTheQuadrature) {
  causticbench::testing::TemporaryFolder folder("lpi_environment_converge");
  const Light coarse = map_light(write_map(folder, "coarse.exr", 12, 6, [](const Vec3& d) {
    return Color(d.y > 0.3f ? 3.0f : 0.2f + 0.1f * d.x, 1.0f, 0.0f);
  }), 10.0);
  const Light spot = spot_light(glm::dvec3(0.3, -1.0, 0.2), 0.2, Color(1.0f));
  const lpi::LightSampleSet set = lpi::geodesic_samples(1, lpi::SampleAt::vertices);
  const double chosen = lpi::hat_quadrature_angle(*set.mesh);
  for (const Light* light : {&coarse, &spot}) {
    const LightFrame posed = pose_light(*light, 0.0);
    auto weights_at = [&](double cell) { return lpi::hat_weights(*set.mesh, environment_quadrature(posed, cell), turn()); };
    const std::vector<double> cells = {4.0 * chosen, 2.0 * chosen, chosen, chosen / 4.0};
    std::vector<std::vector<glm::dvec3>> results;
    for (double cell : cells) results.push_back(weights_at(cell));
    const double total = environment_quadrature(posed, chosen).total().x;
    auto change = [&](size_t a, size_t b) {
      double most = 0.0;
      for (size_t s = 0; s < results[a].size(); ++s) most = std::max(most, std::fabs(results[a][s].x - results[b][s].x));
      return most / total;
    };
    std::printf("%s: largest weight change from cells of 4x, 2x, 1x the chosen size to 1/4: %.2e %.2e %.2e\n",
                light->name.c_str(), change(0, 3), change(1, 3), change(2, 3));
    EXPECT_LT(change(2, 3), 2e-3);
    EXPECT_LT(change(2, 3), change(0, 3));
  }
}

namespace {

// A direction of the level-0 set from above, tilted (light from there reaches the floor through the
// sphere).
Vec3 sample_from_above() {
  const lpi::LightSampleSet set = lpi::geodesic_samples(0, lpi::SampleAt::vertices);
  Vec3 chosen(0.0f, -1.0f, 0.0f);
  for (const Vec3& d : set.directions)
    if (d.y < 0.95f && d.y > chosen.y) chosen = d;
  return chosen;
}

std::string direction_text(const Vec3& towards_light) {
  return fmt::format("[{:.9g}, {:.9g}, {:.9g}]", -towards_light.x, -towards_light.y, -towards_light.z);
}

}  // namespace

// A tiny bright patch (a Gaussian spot of 1e-6 sr, sigma 4e-4 rad) centred on a light sample renders
// as the directional light of the same irradiance from that sample: its weight on the sample's
// neighbours is about sigma / edge (4e-4 / 1.1 rad), so the images agree within 2e-3 of their largest
// value, through the hat-function sum (grid) and through the spherical-harmonic dot product (sh),
// where it also checks the direction convention: the map projected over the directions photons
// travel (-w) would flip every odd band.
TEST(LpiEnvironment, ATinyPatchRendersAsTheDirectionalLightAtItsSample) {
  const Vec3 sample = sample_from_above();
  ASSERT_GT(sample.y, 0.3f);
  const Scene directional = scene_from_yaml(replace_once(
      kSmallGlassSphere, kSphereLight, "{type: directional, direction: " + direction_text(sample) + ", irradiance: 2}"));
  const Scene patch = scene_from_yaml(replace_once(
      kSmallGlassSphere, kSphereLight,
      "{type: environment, procedural: gaussian_spot, direction: " + direction_text(sample) +
          ", irradiance: 2, solid_angle_sr: 1e-6}"));
  const std::vector<std::string> common = {"light_subdivision=0", "photons_per_sample=20000", "grid_resolution=16",
                                           "orientation=vector", "volume_radius=2.5"};
  for (const std::vector<std::string>& storage : {std::vector<std::string>{"storage=grid", "light_samples=all"},
                                                  std::vector<std::string>{"storage=sh", "sh_order=2"}}) {
    std::vector<std::string> knobs = common;
    knobs.insert(knobs.end(), storage.begin(), storage.end());
    const FrameResult under_directional = causticbench::testing::render(directional, "lpi", knobs);
    const FrameResult under_patch = causticbench::testing::render(patch, "lpi", knobs);
    const double scale = largest(under_directional.caustic);
    ASSERT_GT(scale, 0.0);
    const double difference = largest_difference(under_directional.caustic, under_patch.caustic) / scale;
    std::printf("%s: tiny patch against the directional light: largest difference %.2e of the largest value\n",
                storage[0].c_str(), difference);
    EXPECT_LT(difference, 2e-3) << storage[0];
  }
}

// On a smooth map (degree 2 in the direction) the dot product of storage: sh agrees with the sum
// over light samples of the grid: both integrate the same light samples' volumes against the map,
// one through the samples' hat functions, the other through the least-squares fit of their values.
// Measured relMSE between them 1.8e-5, energy ratio 1.005; bounds 1e-4 and 0.01.
TEST(LpiEnvironment, HarmonicDotProductAgreesWithTheSampleSumOnASmoothMap) {
  causticbench::testing::TemporaryFolder folder("lpi_environment_smooth");
  const std::string path = write_map(folder, "smooth.exr", 64, 32, [](const Vec3& d) {
    return Color(0.5f * (1.0f + d.y) * (1.0f + d.y) + 0.3f * d.x + 0.35f);
  });
  const Scene scene = scene_from_yaml(replace_once(kSmallGlassSphere, kSphereLight, "{type: environment, image: " + path + "}"));
  const std::vector<std::string> common = {"light_subdivision=2", "photons_per_sample=4000", "grid_resolution=16",
                                           "orientation=vector", "volume_radius=2.5"};
  std::vector<std::string> grid = common, harmonic = common;
  grid.push_back("light_samples=all");
  harmonic.insert(harmonic.end(), {"storage=sh", "sh_order=4"});
  const FrameResult summed = causticbench::testing::render(scene, "lpi", grid);
  const FrameResult dotted = causticbench::testing::render(scene, "lpi", harmonic);
  const std::vector<uint8_t>& mask = summed.gbuffer.receiver;
  const double relmse = relative_mse(dotted.caustic, summed.caustic, mask);
  const double energy = masked_sum(dotted.caustic, mask) / masked_sum(summed.caustic, mask);
  std::printf("smooth map: sh dot product against the sample sum: relMSE %.2e, energy ratio %.4f\n", relmse, energy);
  EXPECT_LT(relmse, 1e-4);
  EXPECT_NEAR(energy, 1.0, 0.01);
}

// Model only what the scene requires: a sky whose lower half is dark lights only the samples whose
// hat functions reach above the horizon; `light_samples: auto` shoots those, each with the photons
// the whole set would shoot for it, so the image is the whole set's, bit for bit.
TEST(LpiEnvironment, AutoShootsOnlyTheSamplesTheMapLights) {
  causticbench::testing::TemporaryFolder folder("lpi_environment_sky");
  const std::string path = write_map(folder, "sky.exr", 32, 16, [](const Vec3& d) { return Color(d.y > 0.0f ? 1.0f + d.y : 0.0f); });
  const Scene scene = scene_from_yaml(replace_once(kSmallGlassSphere, kSphereLight, "{type: environment, image: " + path + "}"));
  const std::vector<std::string> common = {"light_subdivision=1", "photons_per_sample=2000", "grid_resolution=12"};
  std::vector<std::string> all = common;
  all.push_back("light_samples=all");
  const FrameResult part = causticbench::testing::render(scene, "lpi", common);
  const FrameResult whole = causticbench::testing::render(scene, "lpi", all);
  const nlohmann::json& record = part.method_record["objects"][0];
  EXPECT_EQ(record["light_sample_set"], "environment");
  EXPECT_EQ(whole.method_record["objects"][0]["light_samples"], 42);
  const int kept = record["light_samples"].get<int>();
  std::printf("sky with a dark lower half: %d of 42 light samples (%s)\n", kept, record["why"].get<std::string>().c_str());
  EXPECT_GT(kept, 15);
  EXPECT_LT(kept, 42);
  EXPECT_NE(record["why"].get<std::string>().find("dark"), std::string::npos);
  ASSERT_GT(largest(whole.caustic), 0.0);
  EXPECT_EQ(part.caustic.values(), whole.caustic.values());
}

// Symmetry turns the read point with the light's direction, which a map's many directions cannot
// share: refused before any photon is shot, naming the light and the knob (the issue's "environment
// light with storage: grid and one light sample").
TEST(LpiEnvironment, SymmetryWithAnEnvironmentLightIsRefused) {
  const Scene scene = scene_from_yaml(replace_once(
      kSmallGlassSphere, kSphereLight,
      "{name: sky, type: environment, procedural: gaussian_spot, direction: [0.3, -1, 0.2], irradiance: 1, solid_angle_sr: 0.1}"));
  for (const std::string symmetry : {"spherical", "axial"}) {
    const std::string message = causticbench::testing::input_error_message([&] {
      causticbench::testing::render(scene, "lpi", {"storage=grid", "symmetry=" + symmetry, "photons_per_sample=1000"});
    });
    EXPECT_NE(message.find("light 'sky' is an environment light, and lpi with symmetry: " + symmetry), std::string::npos)
        << message;
    EXPECT_NE(message.find("use symmetry: none"), std::string::npos) << message;
  }
}

// Against the reference, inside the sampled ball: the glass sphere under a Gaussian spot of 0.1 sr
// and under an image map (a dim sky and a bright sun region, turned 30 degrees), 20,000 photons a light
// sample at light_subdivision 2 (33 and 97 samples kept by light_samples: auto), a 32^3 grid over a
// ball of 3 bounding radii (1.2, the mask's radius). Measured against the footprint reference:
// relMSE 0.0592 and 0.0658, energy ratio 0.9746 and 1.1087; each bound is 1.5 times that deviation
// (relMSE from 0, energy from 1). The ball is pinned: at volume_radius: auto (issue 32) the probes ask
// for 4.8 and 5.7 radii, capped at 4, so the same 32 cells span a third more and the test read 0.066 /
// 0.080 and 0.961 / 1.138, a coarser grid rather than a change in the environment weighting this tests.
// Against progressive photon mapping the image map's ratio read 1.043: ppm's radius bias had added 6 %
// to the reference's sum there (451.7 W/m^2 summed, against 426.1 for the footprint tally and 425.2 for
// a tally of 10 times its photons), hiding a tenth of lpi's excess.
TEST(LpiEnvironment, GlassSphereUnderEnvironmentLightsMatchesTheReference) {
  causticbench::testing::TemporaryFolder folder("lpi_environment_reference");
  const std::string path = write_map(folder, "sun_sky.exr", 64, 32, [](const Vec3& d) {
    const float sun = glm::dot(d, glm::normalize(Vec3(0.5f, 1.0f, 0.1f)));
    return Color(d.y > 0.0f ? 0.05f + (sun > 0.97f ? 40.0f : 0.0f) : 0.0f);
  });
  struct Case {
    std::string light;
    double relmse, energy;
  };
  const std::vector<Case> cases = {
      {"{type: environment, procedural: gaussian_spot, direction: [0.3, -1, 0.2], irradiance: 1, solid_angle_sr: 0.1}", 1.5 * 0.0592, 1.5 * 0.0254},
      {"{type: environment, image: " + path + ", rotation_degrees: 30}", 1.5 * 0.0658, 1.5 * 0.1087}};
  for (const Case& c : cases) {
    const Scene scene = scene_from_yaml(replace_once(kSmallGlassSphere, kSphereLight, c.light));
    const FrameResult reference =
        causticbench::testing::render(scene, "reference", causticbench::testing::kSmallSceneReferenceKnobs);
    const FrameResult lpi = causticbench::testing::render(
        scene, "lpi", {"light_subdivision=2", "photons_per_sample=20000", "grid_resolution=32", "orientation=vector", "volume_radius=3"});
    std::vector<uint8_t> mask(reference.gbuffer.pixel_count(), 0);
    for (size_t pixel = 0; pixel < mask.size(); ++pixel)
      mask[pixel] = reference.gbuffer.receiver[pixel] && glm::length(reference.gbuffer.position[pixel] - Vec3(0.0f, 0.6f, 0.0f)) < 1.2f;
    const double relmse = relative_mse(lpi.caustic, reference.caustic, mask);
    const double energy = masked_sum(lpi.caustic, mask) / masked_sum(reference.caustic, mask);
    std::printf("glass sphere under %s: %d light samples, relMSE %.4f, energy ratio %.4f\n", c.light.c_str(),
                lpi.method_record["objects"][0]["light_samples"].get<int>(), relmse, energy);
    EXPECT_LT(relmse, c.relmse);
    EXPECT_NEAR(energy, 1.0, c.energy);
  }
}

// environment_clamp: per_sample. A mirror ring under a diffuse ceiling (facing down, at the ring's
// top) lit by two small spots, one 25 degrees below the horizon and one 55 degrees above it. The ring's
// walls are vertical, so a mirror keeps the sign of a photon's vertical travel: the light from above
// travels downwards everywhere after it, and each of its samples alone gives the ceiling (normal -y)
// n . E_s <= 0, nothing (as the ceiling itself, which would block that light, would). The spots' hat
// functions share no sample (each reaches 5.26 sigma = 3.8 degrees; subdivision 2's edges are under 20
// degrees), so per_sample renders the two spots exactly as the spot below alone. Summed first
// (combined), the downward light cancels the upward light in the cells under the ceiling (measured:
// energy ratio 0.44 to the spot below alone; bound 0.8, to show the test tells the two apart). Under
// the spot below alone no light travels downwards: per_sample and combined agree to rounding
// (measured 1e-8 of the flux; bound 1e-4 of the largest value).
TEST(LpiEnvironment, PerSampleClampIgnoresLightFromTheOtherSideOfAVerticalMirror) {
  const std::string scene_text = R"(
camera: {type: orthographic, position: [0, -3, 0], look_at: [0, 0, 0], up: [0, 0, 1], view_height: 2.4, resolution: [48, 48]}
lights: [LIGHTS]
objects:
  - shape: {type: quad, size: [6, 6]}
    material: {type: diffuse, albedo: 0.8}
    transform: {rotate: [180, 0, 0], translate: [0, 0.4, 0]}
  - shape: {type: ring, radius: 0.6, height: 0.4}
    material: {type: mirror, reflectance: 0.9}
    transform: {translate: [0, 0.2, 0]}
)";
  const std::string below = "{type: environment, procedural: gaussian_spot, direction: [0.2, 0.422618, 0.883723], "
                            "irradiance: 1, solid_angle_sr: 0.001}";
  const std::string above = "{type: environment, procedural: gaussian_spot, direction: [0.2, -0.819152, 0.537], "
                            "irradiance: 1, solid_angle_sr: 0.001}";
  const Scene below_only = scene_from_yaml(replace_once(scene_text, "LIGHTS", below));
  const Scene both = scene_from_yaml(replace_once(scene_text, "LIGHTS", below + ", " + above));
  auto render = [&](const Scene& scene, const std::string& clamp) {
    // One ball for both scenes (auto would fit each scene's own, and the comparison is of the clamp alone).
    return causticbench::testing::render(scene, "lpi", {"light_subdivision=2", "photons_per_sample=5000", "grid_resolution=24",
                                                        "orientation=vector", "environment_clamp=" + clamp,
                                                        "volume_radius=3"});
  };
  const FrameResult per_sample_below = render(below_only, "per_sample");
  const FrameResult per_sample_both = render(both, "per_sample");
  const FrameResult combined_below = render(below_only, "combined");
  const FrameResult combined_both = render(both, "combined");
  EXPECT_EQ(per_sample_both.method_record["objects"][0]["environment"]["clamp"], "per_sample");
  const std::vector<uint8_t>& mask = per_sample_below.gbuffer.receiver;
  const double scale = largest(per_sample_below.caustic);
  ASSERT_GT(scale, 0.0);
  const double above_difference = largest_difference(per_sample_both.caustic, per_sample_below.caustic) / scale;
  const double clamp_difference = largest_difference(combined_below.caustic, per_sample_below.caustic) / scale;
  const double combined_ratio = masked_sum(combined_both.caustic, mask) / masked_sum(combined_below.caustic, mask);
  std::printf("ring under a ceiling, spot above added: per_sample largest difference %.2e, combined energy ratio %.4f; "
              "spot below alone: combined against per_sample %.2e\n",
              above_difference, combined_ratio, clamp_difference);
  EXPECT_LT(above_difference, 1e-6);
  EXPECT_LT(combined_ratio, 0.8);
  EXPECT_LT(clamp_difference, 1e-4);
}
