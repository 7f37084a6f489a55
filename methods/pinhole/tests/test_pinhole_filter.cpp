// pinhole's own footprint filter on a mip-mapped light cube map (methods/pinhole/cube_filter.h): it
// integrates to one, keeps a compact light's irradiance, agrees with OpenImageIO's on smooth maps, and
// its skip of footprints that reach no light changes nothing.
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include <unistd.h>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "core/image_statistics.h"
#include "methods/pinhole/cube_filter.h"
#include "methods/pinhole/light_map.h"
#include "methods/pinhole/tests/test_scenes.h"
#include "tests/test_support.h"

using namespace causticbench;
using causticbench::testing::scene_from_yaml;

namespace {

DistantLights lights_of(const std::string& light) {
  static std::vector<std::unique_ptr<Scene>> scenes;  // DistantLights may point into the scene (environment maps)
  scenes.push_back(std::make_unique<Scene>(scene_from_yaml(
      "camera: {position: [0, 3, 3], look_at: [0, 0, 0], resolution: [8, 8]}\nlights: [" + light +
      "]\nobjects:\n  - shape: {type: sphere, radius: 1}\n    material: {type: mirror, reflectance: 1}\n")));
  SceneFrame frame(*scenes.back(), 0);
  return DistantLights(frame, Vec3(0.0f));
}

std::string disk_light_towards(const Vec3& towards_light, float irradiance, float solid_angle) {
  return fmt::format("{{type: directional, direction: [{}, {}, {}], irradiance: {}, solid_angle_sr: {}}}", -towards_light.x,
                     -towards_light.y, -towards_light.z, irradiance, solid_angle);
}

// A random footprint around `direction`: tangent gradients of lengths from a thousandth of a radian to
// 2 (the whole map), plus a random normal component (reflection gradients are not tangent).
void random_gradients(Random& random, const Vec3& direction, Vec3& gradient_u, Vec3& gradient_v) {
  Vec3 t, b;
  orthonormal_basis(direction, t, b);
  float angle = 2.0f * kPi * random.uniform();
  Vec3 axis_u = std::cos(angle) * t + std::sin(angle) * b, axis_v = -std::sin(angle) * t + std::cos(angle) * b;
  float length_u = std::pow(10.0f, -3.0f + 3.3f * random.uniform()), length_v = std::pow(10.0f, -3.0f + 3.3f * random.uniform());
  gradient_u = length_u * axis_u + 0.1f * length_u * (random.uniform() - 0.5f) * direction;
  gradient_v = length_v * axis_v;
}

}  // namespace

TEST(PinholeCubeFilter, IntegratesToOne) {
  // A constant map: every probe, every level, every face border holds the constant, and the probe
  // weights sum to one, so any footprint returns it: small ones, ones that cross faces and cube corners,
  // and ones wider than the map. An odd face size makes uneven boxes at some levels.
  for (int resolution : {16, 12}) {
    std::vector<float> rgb(6u * resolution * resolution * 3);
    for (size_t i = 0; i < rgb.size(); i += 3) rgb[i] = 1.7f, rgb[i + 1] = 0.3f, rgb[i + 2] = 2.0f;
    CubeFilter filter(rgb, resolution);
    Random random(11, 0);
    std::vector<Vec3> directions = {glm::normalize(Vec3(1, 1, 1)), glm::normalize(Vec3(1, 0.999f, 0.2f)), Vec3(0, 0, 1)};
    for (int i = 0; i < 2000; ++i) directions.push_back(sample_sphere(random.uniform(), random.uniform()));
    for (const Vec3& direction : directions) {
      for (bool anisotropic : {false, true}) {
        Vec3 gradient_u, gradient_v;
        random_gradients(random, direction, gradient_u, gradient_v);
        Color value = filter.lookup(direction, gradient_u, gradient_v, anisotropic);
        ASSERT_NEAR(value.r, 1.7f, 2e-5f) << direction.x << " " << direction.y << " " << direction.z << " " << anisotropic;
        ASSERT_NEAR(value.g, 0.3f, 1e-5f);
        ASSERT_NEAR(value.b, 2.0f, 2e-5f);
      }
    }
  }
}

TEST(PinholeCubeFilter, ConstantLightGivesTheSameIrradianceFilteredAndUnfiltered) {
  // The same at the method's level: under a uniform sky (two hemispherical disk lights, one from above
  // and one from below), the filtered renders equal the unfiltered one.
  Scene scene = scene_from_yaml(causticbench::testing::pinhole_mirror_sphere(
      "[{type: directional, direction: [0, -1, 0], irradiance: 1, solid_angle_sr: 6.2831853},\n"
      "         {type: directional, direction: [0, 1, 0], irradiance: 1, solid_angle_sr: 6.2831853}]",
      16));
  const std::vector<std::string> common = {"samples=300", "environment_resolution=16"};
  // The unfiltered render on the float map: the vector fetch would read a sky lit everywhere from the
  // shared-exponent copy (packed_texels.h), whose 9-bit rounding of the constant (1.5e-4 here) is not
  // the filter's.
  ::setenv("CAUSTICBENCH_PINHOLE_SCALAR_FETCH", "1", 1);
  FrameResult unfiltered = causticbench::testing::render(scene, "pinhole", common);
  ::unsetenv("CAUSTICBENCH_PINHOLE_SCALAR_FETCH");
  double flux = masked_sum(unfiltered.caustic, unfiltered.gbuffer.receiver);
  ASSERT_GT(flux, 0.0);
  for (const char* filtering : {"filtering=isotropic", "filtering=anisotropic"}) {
    std::vector<std::string> knobs = common;
    knobs.push_back(filtering);
    FrameResult filtered = causticbench::testing::render(scene, "pinhole", knobs);
    EXPECT_LT(relative_mse(filtered.caustic, unfiltered.caustic, unfiltered.gbuffer.receiver), 1e-8) << filtering;
    EXPECT_NEAR(masked_sum(filtered.caustic, unfiltered.gbuffer.receiver) / flux, 1.0, 1e-5) << filtering;
  }
}

TEST(PinholeCubeFilter, KeepsACompactLightsIrradiance) {
  // Fig. 4's 0.0008 sr light on a face centre, on a seam between two faces and at a cube corner:
  // integrate the filtered lookups over a square of the tangent plane around it (dω = dA / (1 + x² +
  // y²)^{3/2}), as the OpenImageIO test does, with no footprint and with footprints that stay on level 0
  // (half a texel round, and 3 and 8 texels long and at most 0.4 wide, probed along their length). A normalised filter moves
  // light but keeps it, so the integral must equal the light's 3 W/m² within 2 %. Footprints that read
  // coarser levels keep it less well near seams and corners, where a level's texels change size across
  // the footprint (README, "The filter": measured 2 to 10 % lost or gained).
  const int resolution = 64;
  for (Vec3 towards_light : {Vec3(0.0f, 0.0f, 1.0f), glm::normalize(Vec3(1.0f, 0.0f, 1.0f)), glm::normalize(Vec3(1.0f, 1.0f, 1.0f))}) {
    DistantLights lights = lights_of(disk_light_towards(towards_light, 3.0f, 0.0008f));
    LightCubeMap map(lights, resolution);
    CubeFilter filter(map.texels(), resolution);
    Vec3 axis = glm::normalize(towards_light), tangent, bitangent;
    orthonormal_basis(axis, tangent, bitangent);
    const float texel = 2.0f / resolution;
    for (auto [along_u, along_v, anisotropic] : {std::tuple{0.0f, 0.0f, false}, std::tuple{0.0f, 0.0f, true},
                                                 std::tuple{0.5f, 0.5f, false}, std::tuple{3.0f, 0.3f, true},
                                                 std::tuple{8.0f, 0.4f, true}}) {
      const Vec3 gradient_u = along_u * texel * glm::normalize(tangent + 0.3f * bitangent);
      const Vec3 gradient_v = along_v * texel * glm::normalize(bitangent - 0.3f * tangent);
      // Wide enough for the coarsest level read (footprints of 3 texels at the corner read level 3, whose
      // bilinear support reaches 16 level-0 texels, 0.5 rad).
      const double integral = causticbench::testing::integrate_around(axis, 0.8, 300, [&](const Vec3& direction) {
        return filter.lookup(direction, gradient_u, gradient_v, anisotropic).r;
      });
      EXPECT_NEAR(integral, 3.0, 0.06) << "light towards " << towards_light.x << " " << towards_light.y << " "
                                       << towards_light.z << ", footprint " << along_u << " x " << along_v
                                       << (anisotropic ? " anisotropic" : " isotropic");
    }
  }
}

TEST(PinholeCubeFilter, AgreesWithOpenImageIoOnSmoothMaps) {
  // A wide Gaussian spot: the own filter (cube map) and OpenImageIO's (lat-long, twice as high) are
  // both box-like filters of the same footprint, so on a map that varies slowly across the footprint
  // they agree closely on average (measured: mean 0.04 % of the peak radiance) and within a few percent
  // where the spot's curvature meets their different kernels (largest 5.4 %). Bounds: mean 0.5 %,
  // largest 8 % of the peak.
  DistantLights lights = lights_of(
      "{type: environment, procedural: gaussian_spot, direction: [0.5, -1, 0.3], irradiance: 1, solid_angle_sr: 0.3}");
  LightCubeMap map(lights, 128);
  CubeFilter filter(map.texels(), 128);
  FilteredLightMap oiio(lights, 256);
  float peak = 0.0f;
  for (size_t i = 0; i < map.texels().size(); i += 3) peak = std::max(peak, map.texels()[i]);
  Random random(5, 0);
  double largest = 0.0, mean = 0.0;
  for (int i = 0; i < 400; ++i) {
    Vec3 direction = sample_sphere(random.uniform(), random.uniform());
    Vec3 t, b;
    orthonormal_basis(direction, t, b);
    // Footprints of 1 to 8 texels of the cube map (0.016 rad a texel), up to 8:1.
    float length_u = 0.016f * (1.0f + 7.0f * random.uniform()), length_v = 0.016f * (1.0f + 2.0f * random.uniform());
    for (bool anisotropic : {false, true}) {
      Color own = filter.lookup(direction, length_u * t, length_v * b, anisotropic);
      Color theirs = oiio.lookup(direction, length_u * t, length_v * b, anisotropic);
      largest = std::max(largest, static_cast<double>(std::abs(own.r - theirs.r)) / peak);
      mean += std::abs(own.r - theirs.r) / peak / 800.0;
    }
  }
  EXPECT_LT(largest, 0.08);
  EXPECT_LT(mean, 0.005);
  fmt::print("own against OpenImageIO: largest difference {:.4f}, mean {:.4f} of the peak\n", largest, mean);
}

TEST(PinholeCubeFilter, SkipChangesNothing) {
  // The lookups themselves: a compact light and footprints of every size, with and without the skip,
  // bit for bit; most of them are skipped, some reach the light.
  const int resolution = 32;
  DistantLights lights = lights_of(disk_light_towards(glm::normalize(Vec3(1.0f, 1.0f, 0.999f)), 3.0f, 0.0008f));
  LightCubeMap map(lights, resolution);
  CubeFilter filter(map.texels(), resolution);
  ASSERT_FALSE(filter.lit_everywhere());
  Random random(9, 0);
  size_t skipped = 0, lit = 0;
  for (int i = 0; i < 200000; ++i) {
    // Half of the directions near the light, so that footprints graze it.
    Vec3 direction = i % 2 ? sample_sphere(random.uniform(), random.uniform())
                           : glm::normalize(glm::normalize(Vec3(1.0f, 1.0f, 0.999f)) +
                                            0.4f * (sample_sphere(random.uniform(), random.uniform())));
    Vec3 gradient_u, gradient_v;
    random_gradients(random, direction, gradient_u, gradient_v);
    for (bool anisotropic : {false, true}) {
      Color with = filter.lookup(direction, gradient_u, gradient_v, anisotropic, true);
      Color without = filter.lookup(direction, gradient_u, gradient_v, anisotropic, false);
      ASSERT_EQ(std::memcmp(&with, &without, sizeof(Color)), 0)
          << without.r << " at " << direction.x << " " << direction.y << " " << direction.z;
      skipped += !filter.may_reach_light(direction, gradient_u, gradient_v, anisotropic);
      lit += without.r > 0.0f;
    }
  }
  EXPECT_GT(skipped, 80000u);
  EXPECT_GT(lit, 5000u);
}

TEST(PinholeCubeFilter, SkipChangesNoRender) {
  // And whole renders of the ring (its compact light on a cube-map seam), bit for bit.
  Scene scene = load_scene(std::string(CAUSTICBENCH_SCENES) + "/ring.yaml");
  set_resolution(scene, 24, 24);
  for (const char* filtering : {"filtering=isotropic", "filtering=anisotropic"}) {
    const std::vector<std::string> knobs = {"samples=200", "environment_resolution=64", filtering};
    FrameResult with = causticbench::testing::render(scene, "pinhole", knobs);
    ::setenv("CAUSTICBENCH_PINHOLE_NO_SKIP", "1", 1);
    FrameResult without = causticbench::testing::render(scene, "pinhole", knobs);
    ::unsetenv("CAUSTICBENCH_PINHOLE_NO_SKIP");
    ASSERT_GT(masked_sum(without.caustic, without.gbuffer.receiver), 0.0);
    ASSERT_EQ(with.caustic.values().size(), without.caustic.values().size());
    EXPECT_EQ(std::memcmp(with.caustic.values().data(), without.caustic.values().data(),
                          with.caustic.values().size() * sizeof(float)), 0) << filtering;
  }
}

TEST(PinholeCubeFilter, VulkanAgreesWithTheCpu) {
  // The own filter on both backends (lavapipe without a GPU): the shader repeats CubeFilter's
  // arithmetic probe by probe on the same texels, so the images differ by float rounding (the GPU's
  // log2 and sums), far below what separates two filters (measured relMSE below 1e-12). Bound: relMSE
  // 1e-9 and flux within 1e-5, on a wide light and on the ring's compact light, which sits on a
  // cube-map seam.
  Scene sphere = scene_from_yaml(causticbench::testing::pinhole_mirror_sphere(
      "[{type: environment, procedural: gaussian_spot, direction: [0.4, -1, 0], irradiance: 1, solid_angle_sr: 0.2}]", 24));
  Scene ring = load_scene(std::string(CAUSTICBENCH_SCENES) + "/ring.yaml");
  set_resolution(ring, 24, 24);
  for (const Scene* scene : {&sphere, &ring}) {
    for (const char* filtering : {"filtering=isotropic", "filtering=anisotropic"}) {
      const std::vector<std::string> knobs = {"samples=300", "environment_resolution=64", filtering};
      FrameResult cpu = causticbench::testing::render(*scene, "pinhole", knobs);
      std::vector<std::string> vulkan_knobs = knobs;
      vulkan_knobs.push_back("backend=vulkan");
      FrameResult vulkan = causticbench::testing::render(*scene, "pinhole", vulkan_knobs);
      const double flux = masked_sum(cpu.caustic, cpu.gbuffer.receiver);
      ASSERT_GT(flux, 0.0) << filtering;
      const double error = relative_mse(vulkan.caustic, cpu.caustic, cpu.gbuffer.receiver);
      fmt::print("{} {}: relMSE {:.3g}, flux ratio {:.8f}\n", scene == &ring ? "ring" : "sphere", filtering, error,
                 masked_sum(vulkan.caustic, cpu.gbuffer.receiver) / flux);
      EXPECT_LT(error, 1e-9) << filtering;
      EXPECT_NEAR(masked_sum(vulkan.caustic, cpu.gbuffer.receiver) / flux, 1.0, 1e-5) << filtering;
      EXPECT_EQ(vulkan.method_record["filter_implementation"], "own");
      EXPECT_EQ(vulkan.method_record["gpu_sampler_warning"], "");
    }
  }
}

TEST(PinholeCubeFilter, GpubenchReplaysAFilteredDump) {
  // A CPU run's --dump-frame carries the own filter's levels, so that causticbench-gpubench replays the
  // filtered frame with the same filter and gpu-compare finds it equal to the CPU's image.
  namespace fs = std::filesystem;
  fs::path folder = fs::temp_directory_path() / fmt::format("causticbench_filtered_dump_{}", getpid());
  fs::remove_all(folder);
  std::string output, dump = (folder / "dump").string();
  int code = causticbench::testing::run_command(
      std::string(CAUSTICBENCH_BINARY) + " -q render " + CAUSTICBENCH_SCENES + "/ring.yaml --method pinhole --set samples=300 " +
          "--set filtering=anisotropic --set environment_resolution=64 --resolution 32x32 --out " + (folder / "out").string() +
          " --dump-frame " + dump,
      output);
  ASSERT_EQ(code, 0) << output;
  code = causticbench::testing::run_command(std::string(CAUSTICBENCH_GPUBENCH) + " " + dump + " --repetitions 1", output);
  ASSERT_EQ(code, 0) << output;
  code = causticbench::testing::run_command(std::string(CAUSTICBENCH_BINARY) + " gpu-compare " + dump, output);
  EXPECT_EQ(code, 0) << output;
  EXPECT_NE(output.find("): agree"), std::string::npos) << output;
  fs::remove_all(folder);
}
