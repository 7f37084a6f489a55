// pinhole (Wand & Strasser 2003): sampling strategies, differential geometry, the light map,
// convergence to the reference, and numerical extremes.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include "core/image_statistics.h"
#include "core/optics.h"
#include "core/scene.h"
#include "methods/frame_dump.h"
#include "methods/pinhole/frame_data.h"
#include "methods/pinhole/light_map.h"
#include "methods/pinhole/packed_texels.h"
#include "methods/pinhole/pinhole.h"
#include "methods/pinhole/reflector_sampling.h"
#include "methods/pinhole/texel_fetch.h"
#include "methods/pinhole/throughput.h"
#include "methods/pinhole/tests/test_scenes.h"
#include "tests/test_support.h"

using namespace causticbench;
using causticbench::testing::render;
using causticbench::testing::scene_from_yaml;

namespace {

Scene one_reflector(const std::string& shape, const std::string& light = "{type: directional, direction: [0, -1, 0], irradiance: 1, solid_angle_sr: 0.01}") {
  return scene_from_yaml("camera: {position: [0, 3, 3], look_at: [0, 0, 0], resolution: [8, 8]}\nlights: [" + light +
                         "]\nobjects:\n  - shape: " + shape + "\n    material: {type: mirror, reflectance: 1}\n");
}

SampleSet draw(const Scene& scene, size_t target, SamplingStrategy strategy) {
  SceneFrame frame(scene, 0);
  return sample_reflectors(frame, {0}, target, strategy, 7);
}

}  // namespace

TEST(PinholeSampling, CountsLandNearTheTarget) {
  Scene scene = one_reflector("{type: sphere, radius: 1}");
  for (SamplingStrategy strategy : {SamplingStrategy::random, SamplingStrategy::grid, SamplingStrategy::quantized_grid,
                                    SamplingStrategy::neighborhood}) {
    for (size_t target : {50u, 2000u}) {
      SampleSet set = draw(scene, target, strategy);
      // The cell size or sphere diameter is bisected until the count is within 1 % where possible;
      // the stated tolerance is 5 %.
      EXPECT_NEAR(static_cast<double>(set.samples.size()), static_cast<double>(target), 0.05 * target)
          << static_cast<int>(strategy);
      EXPECT_NEAR(set.total_area, 4.0 * kPiDouble, 1e-9);
      double area_sum = 0.0;
      for (const ReflectorSample& sample : set.samples) area_sum += sample.area;
      EXPECT_NEAR(area_sum, set.total_area, 1e-3 * set.total_area);  // each sample stands for A / N
    }
  }
}

TEST(PinholeSampling, RandomAndNeighbourhoodAreAreaUniform) {
  // Chi-square over 8 equal-area latitude bands x 8 longitude sectors of the unit sphere; 63 degrees of
  // freedom: the 99.9 % quantile is 103.4. Fixed seed.
  Scene scene = one_reflector("{type: sphere, radius: 1}");
  for (SamplingStrategy strategy : {SamplingStrategy::random, SamplingStrategy::neighborhood}) {
    SampleSet set = draw(scene, 6400, strategy);
    std::vector<double> counts(64, 0.0);
    for (const ReflectorSample& sample : set.samples) {
      int band = std::min(7, static_cast<int>((sample.position.y + 1.0f) * 4.0f));
      double phi = std::atan2(sample.position.z, sample.position.x) + kPiDouble;
      int sector = std::min(7, static_cast<int>(phi / (2.0 * kPiDouble) * 8.0));
      counts[band * 8 + sector] += 1.0;
    }
    double expected = static_cast<double>(set.samples.size()) / 64.0, chi_square = 0.0;
    for (double count : counts) chi_square += (count - expected) * (count - expected) / expected;
    EXPECT_LT(chi_square, 103.4) << static_cast<int>(strategy);
    // The neighbourhood sampling is far more even than random (the paper's point): well below the mean
    // of the chi-square distribution (63).
    if (strategy == SamplingStrategy::neighborhood) {
      EXPECT_LT(chi_square, 30.0);
    }
  }
  // Mesh sampling: a box, area-uniform over its faces (the 2 x 1 x 1 box has face areas 2, 2, 2, 2, 1, 1).
  Scene box = one_reflector("{type: box, size: [2, 1, 1]}");
  SampleSet set = draw(box, 10000, SamplingStrategy::random);
  int on_small_faces = 0;
  for (const ReflectorSample& sample : set.samples) on_small_faces += std::abs(std::abs(sample.position.x) - 1.0f) < 1e-4f;
  // Expected 2 / 10 of the samples; binomial standard deviation 40: 5 sigma is 200.
  EXPECT_NEAR(on_small_faces, 2000, 200);
}

TEST(PinholeSampling, NeighbourhoodKeepsItsMinimumSpacing) {
  Scene scene = one_reflector("{type: ring, radius: 1, height: 0.5}");
  SampleSet set = draw(scene, 500, SamplingStrategy::neighborhood);
  ASSERT_GT(set.cell_or_diameter, 0.0);
  float diameter2 = static_cast<float>(set.cell_or_diameter * set.cell_or_diameter);
  for (size_t i = 0; i < set.samples.size(); ++i) {
    for (size_t j = i + 1; j < set.samples.size(); ++j) {
      Vec3 offset = set.samples[i].position - set.samples[j].position;
      ASSERT_GE(glm::dot(offset, offset), diameter2 * (1.0f - 1e-5f)) << i << " " << j;
    }
  }
}

TEST(PinholeSampling, QuantizedGridSnapsToCellCentres) {
  Scene scene = one_reflector("{type: sphere, radius: 1}");
  SampleSet set = draw(scene, 300, SamplingStrategy::quantized_grid);
  double cell = set.cell_or_diameter;
  for (const ReflectorSample& sample : set.samples) {
    glm::dvec3 in_cell = glm::dvec3(sample.position) / cell - glm::floor(glm::dvec3(sample.position) / cell);
    EXPECT_NEAR(in_cell.x, 0.5, 1e-3);
    EXPECT_NEAR(in_cell.z, 0.5, 1e-3);
  }
}

TEST(PinholeDifferentials, CurvatureOfASphereAndACylinder) {
  // Sphere of radius 2: both principal curvatures 1/2. Cylinder (thin ring) of radius 0.5: 2 and 0.
  Scene sphere = one_reflector("{type: sphere, radius: 2}");
  SampleSet set = draw(sphere, 400, SamplingStrategy::neighborhood);
  estimate_differentials(set, 1.5 * set.spacing);
  double sum_u = 0.0, sum_v = 0.0;
  for (const ReflectorSample& sample : set.samples) {
    sum_u += sample.curvature_u;
    sum_v += sample.curvature_v;
  }
  EXPECT_NEAR(sum_u / set.samples.size(), 0.5, 0.02);
  EXPECT_NEAR(sum_v / set.samples.size(), 0.5, 0.02);

  Scene cylinder = one_reflector("{type: ring, radius: 0.5, height: 4}");
  SampleSet ring = draw(cylinder, 800, SamplingStrategy::neighborhood);
  estimate_differentials(ring, 1.5 * ring.spacing);
  double large = 0.0, small = 0.0, along_axis = 0.0;
  size_t count = 0;
  for (const ReflectorSample& sample : ring.samples) {
    if (sample.position.y < 0.5f || sample.position.y > 3.5f) continue;  // away from the rims
    large += std::max(std::abs(sample.curvature_u), std::abs(sample.curvature_v));
    small += std::min(std::abs(sample.curvature_u), std::abs(sample.curvature_v));
    // The flat direction is the cylinder's axis.
    const Vec3& flat = std::abs(sample.curvature_u) < std::abs(sample.curvature_v) ? sample.direction_u : sample.direction_v;
    along_axis += std::abs(flat.y);
    ++count;
  }
  ASSERT_GT(count, 300u);
  EXPECT_NEAR(large / count, 2.0, 0.1);
  EXPECT_NEAR(small / count, 0.0, 0.05);
  EXPECT_GT(along_axis / count, 0.98);
}

TEST(PinholeLightMap, HoldsTheExactIrradianceOfEveryLight) {
  // A compact disk source, a sub-texel source (1e-6 sr) and a Gaussian spot: the map's integral of
  // radiance over solid angle equals each light's irradiance.
  for (const std::string& light : {std::string("{type: directional, direction: [0.3, -1, 0.2], irradiance: 2, solid_angle_sr: 0.01}"),
                                   std::string("{type: directional, direction: [0.3, -1, 0.2], irradiance: 2, solid_angle_sr: 0.000001}"),
                                   std::string("{type: environment, procedural: gaussian_spot, direction: [0, -1, 0], irradiance: 2, solid_angle_sr: 0.05}")}) {
    Scene scene = one_reflector("{type: sphere, radius: 1}", light);
    SceneFrame frame(scene, 0);
    DistantLights lights(frame, Vec3(0.0f));
    LightCubeMap map(lights, 64);
    EXPECT_NEAR(map.integral().r, 2.0f, 2e-3f) << light;
  }
}

TEST(PinholeLightMap, CubeMapAndFilteredLatLongAgree) {
  // A wide Gaussian spot: the cube map (bilinear) and the OpenImageIO lat-long texture (tiny footprint)
  // give the same radiance in the same directions, which pins down both layouts.
  Scene scene = one_reflector("{type: sphere, radius: 1}",
                              "{type: environment, procedural: gaussian_spot, direction: [0.5, -1, 0.3], irradiance: 1, solid_angle_sr: 0.3}");
  SceneFrame frame(scene, 0);
  DistantLights lights(frame, Vec3(0.0f));
  LightCubeMap cube(lights, 128);
  FilteredLightMap filtered(lights, 256);
  Random random(3, 0);
  for (int i = 0; i < 200; ++i) {
    Vec3 direction = sample_sphere(random.uniform(), random.uniform());
    Color a = cube.lookup(direction), b = filtered.lookup(direction, Vec3(1e-4f, 0, 0), Vec3(0, 0, 1e-4f), true);
    EXPECT_NEAR(a.r, b.r, 0.03f * std::max(1.0f, a.r)) << direction.x << " " << direction.y << " " << direction.z;
  }
  // Round trip of the cube layout.
  for (int i = 0; i < 200; ++i) {
    Vec3 direction = sample_sphere(random.uniform(), random.uniform());
    int face;
    float s, t;
    LightCubeMap::direction_to_texel(direction, 64, face, s, t);
    Vec3 back = LightCubeMap::texel_direction(face, s / 64.0f, t / 64.0f);
    EXPECT_GT(glm::dot(back, direction), 0.99999f);
  }
}

TEST(PinholeLightMap, FilteredLookupsKeepACompactLightsIrradiance) {
  // Fig. 4's 0.0008 sr light, anywhere on the sphere: on the lat-long seam (u = 0, where the ring
  // scene's light sits; an OpenEXR texture lost a column there, 20 % of the light), towards the pole,
  // and on the far side. Integrate the lookups over a square of the tangent plane around the light
  // (dω = dA / |1 + x² + y²|^{3/2}); bilinear interpolation keeps the integral, so it must equal the
  // light's irradiance, 3 W/m², to the 2 % that the lat-long's sin θ weighting across a texel allows.
  for (Vec3 towards_light : {Vec3(0.0f, 0.5f, -0.8660254f), Vec3(0.2f, 0.95f, 0.1f), Vec3(0.3f, -0.2f, 0.9f)}) {
    Vec3 travel = -towards_light;
    Scene scene = one_reflector("{type: sphere, radius: 1}",
                                fmt::format("{{type: directional, direction: [{}, {}, {}], irradiance: 3, solid_angle_sr: 0.0008}}",
                                            travel.x, travel.y, travel.z));
    SceneFrame frame(scene, 0);
    DistantLights lights(frame, Vec3(0.0f));
    FilteredLightMap filtered(lights, 512);
    const double integral = causticbench::testing::integrate_around(
        glm::normalize(towards_light), 0.05, 240,
        [&](const Vec3& direction) { return filtered.lookup(direction, Vec3(0.0f), Vec3(0.0f), true).r; });
    EXPECT_NEAR(integral, 3.0, 0.06) << "light towards " << towards_light.x << " " << towards_light.y << " " << towards_light.z;
  }
}

TEST(PinholeLightMap, StaleTextureFilesOfDeadProcessesAreRemoved) {
  // A child that has exited and been reaped stands for a killed run; this process and a live one keep theirs.
  pid_t child = fork();
  if (child == 0) _exit(0);
  ASSERT_GT(child, 0);
  waitpid(child, nullptr, 0);
  std::filesystem::path folder = std::filesystem::temp_directory_path() / fmt::format("causticbench-stale-test-{}", getpid());
  std::filesystem::create_directories(folder);
  auto touch = [&](const std::string& name) { std::ofstream(folder / name) << "x"; return folder / name; };
  auto dead = touch(fmt::format("causticbench-lightmap-{}-0.tx", child));
  auto own = touch(fmt::format("causticbench-lightmap-{}-3.tx", getpid()));
  auto live = touch("causticbench-lightmap-1-0.tx");  // init never exits
  auto unrelated = touch(fmt::format("something-else-{}-0.tx", child));
  EXPECT_EQ(remove_stale_light_map_files(folder), 1u);
  EXPECT_FALSE(std::filesystem::exists(dead));
  EXPECT_TRUE(std::filesystem::exists(own));
  EXPECT_TRUE(std::filesystem::exists(live));
  EXPECT_TRUE(std::filesystem::exists(unrelated));
  std::filesystem::remove_all(folder);
}

namespace {

const std::string kMirrorSphere = causticbench::testing::pinhole_mirror_sphere();

}  // namespace

TEST(Pinhole, ConvergesToTheReference) {
  Scene scene = scene_from_yaml(kMirrorSphere);
  FrameResult reference = render(scene, "reference", {"photons_per_pass=400000", "max_passes=40", "target_error=0"});
  std::vector<double> errors;
  for (int samples : {30, 300, 3000}) {
    FrameResult run = render(scene, "pinhole", {"samples=" + std::to_string(samples)});
    errors.push_back(relative_mse(run.caustic, reference.caustic, run.gbuffer.receiver));
  }
  EXPECT_LT(errors[1], errors[0]);
  EXPECT_LT(errors[2], errors[1]);
  // 10,000 samples under the wide light, each filtering (methods/pinhole/README.md, "Measured": the cost
  // and energy of filtering on a wide light quote these lines). Unfiltered, the dots of single samples
  // are gone at 10,000 and the energy is the sampling's; filtered, each footprint's integral keeps the
  // map's light. Each within 3 % of the reference (measured 1.0198 / 1.0204 / 1.0203, relMSE 0.0015
  // each; the reference's own error is 3e-4 here). The 2 % above the reference is common to the three, so
  // it is not the filters'; where it comes from is not yet measured. The filtered images are closer than
  // the unfiltered one at 30 samples.
  const double reference_flux = masked_sum(reference.caustic, reference.gbuffer.receiver);
  for (const char* filtering : {"filtering=none", "filtering=isotropic", "filtering=anisotropic"}) {
    FrameResult run = render(scene, "pinhole", {"samples=10000", filtering});
    const double energy = masked_sum(run.caustic, run.gbuffer.receiver) / reference_flux;
    std::printf("10,000 samples, %s: energy %.4f, relMSE %.4f, render %.0f ms\n", filtering, energy,
                relative_mse(run.caustic, reference.caustic, run.gbuffer.receiver), run.timings.render_milliseconds);
    EXPECT_NEAR(energy, 1.0, 0.03) << filtering;
    if (std::string(filtering) != "filtering=none")
      EXPECT_LT(relative_mse(run.caustic, reference.caustic, run.gbuffer.receiver), errors[0]) << filtering;
  }
}

// interaction: refract is Wand's single refraction (methods/pinhole/README.md, "Refraction: one
// interface"): the receiver is taken to lie in the glass, the light refracted at the sample goes on in a
// straight line. On a closed glass sphere over a floor that is not the physics (the light leaves through
// a second interface), but it is a model with a closed form to check the method against: parallel light
// (1 W/m^2) through the sphere's cross-section, refracted at entry with weight 1 - F and followed in a
// straight line to the floor, lands on the visible floor (outside the silhouette, inside the view) with
// the flux summed here by a 400 x 400 quadrature, independent of pinhole's sampling and lookups
// (0.6227 W; scripts/glass_sphere_ray_model.py: 0.6223). pinhole's sum of E times each pixel's
// footprint squared is that flux within 4 %: measured 2.3 % low at 5,000 samples (pixel centres against the
// integral, and the light's 0.02 sr spread). Without the n^2 of the radiance entering the glass it
// would be 0.44 of it; the physics (two interfaces, the reference) is 0.75 of it, the energy ratio the
// glass capability study measures.
TEST(Pinhole, RefractionIsTheSingleInterfaceModel) {
  Scene scene = load_scene(std::string(CAUSTICBENCH_SCENES) + "/capabilities/glass/directional_light.yaml");
  FrameResult run = render(scene, "pinhole", {"samples=5000", "environment_resolution=32", "interaction=refract"}, 1);
  double method_flux = 0.0;
  for (size_t pixel = 0; pixel < run.gbuffer.pixel_count(); ++pixel)
    if (run.gbuffer.receiver[pixel])
      method_flux += run.caustic.at(pixel, 0) * static_cast<double>(run.gbuffer.footprint[pixel]) * run.gbuffer.footprint[pixel];

  const glm::dvec3 centre(0.0, 2.0, 0.0);
  const double radius = 0.5, ior = 1.5, view_half = 2.0;
  const Vec3 travel = glm::normalize(Vec3(0.4f, -1.0f, 0.1f));  // the scene's light, along its direction of travel
  const glm::dvec3 d(travel);
  const glm::dvec3 across_u = glm::normalize(glm::cross(d, glm::dvec3(0, 0, 1))), across_v = glm::cross(d, across_u);
  const int cells = 400;
  const double cell = 2.0 * radius / cells;
  double model_flux = 0.0;
  for (int i = 0; i < cells; ++i) {
    for (int j = 0; j < cells; ++j) {
      const double u = -radius + (i + 0.5) * cell, v = -radius + (j + 0.5) * cell;
      if (u * u + v * v >= radius * radius) continue;
      // Entry point: the ray through (u, v) of the cross-section meets the sphere at depth -sqrt(R^2 - u^2 - v^2).
      const glm::dvec3 entry = centre + u * across_u + v * across_v - std::sqrt(radius * radius - u * u - v * v) * d;
      const Vec3 normal(glm::normalize(entry - centre));
      Vec3 inside;
      if (!refract(travel, normal, static_cast<float>(ior), inside) || inside.y >= 0.0f) continue;
      const double transmittance = 1.0 - fresnel_dielectric(-glm::dot(travel, normal), static_cast<float>(ior));
      const double t = -entry.y / inside.y;  // straight on to the floor y = 0
      const double x = entry.x + t * inside.x, z = entry.z + t * inside.z;
      if (x * x + z * z > radius * radius && std::abs(x) < view_half && std::abs(z) < view_half)
        model_flux += transmittance * cell * cell;
    }
  }
  EXPECT_NEAR(model_flux, 0.622, 0.005) << "the quadrature against scripts/glass_sphere_ray_model.py";
  EXPECT_NEAR(method_flux / model_flux, 1.0, 0.04) << "pinhole " << method_flux << " W, single-interface model " << model_flux;
}

TEST(Pinhole, ExtremesStayFiniteAndSane) {
  auto all_finite = [](const FrameResult& result) {
    for (float value : result.caustic.values()) {
      if (!std::isfinite(value) || value < 0.0f) return false;
    }
    return true;
  };
  Scene scene = scene_from_yaml(kMirrorSphere);
  FrameResult one = render(scene, "pinhole", {"samples=1"});
  EXPECT_TRUE(all_finite(one));
  EXPECT_EQ(one.counters[0].second, 1.0);
  // Unfiltered: a million filtered lookups a pixel would only make the case slow (the filter is covered
  // at the other extremes here, which use the default).
  FrameResult million = render(scene, "pinhole", {"samples=1000000", "sampling=random", "filtering=none"});
  EXPECT_TRUE(all_finite(million));
  // A receiver on the reflector itself (the cup's diffuse+mirror bottom, lit by its own wall): the
  // epsilon term keeps the samples under a receiver point finite.
  Scene cup = scene_from_yaml(R"(
camera: {position: [0, 3, 0.5], look_at: [0, 0, 0], resolution: [24, 24]}
lights: [{type: point, position: [-2, 2, 0], intensity: 5}]
objects:
  - shape: {type: cup, radius: 1, height: 1}
    material: {type: diffuse_mirror, albedo: 0.3, reflectance: 0.6}
)");
  FrameResult self = render(cup, "pinhole", {"samples=2000"});
  EXPECT_TRUE(all_finite(self));
  EXPECT_GT(masked_sum(self.caustic, self.gbuffer.receiver), 0.0);
  FrameResult no_epsilon = render(cup, "pinhole", {"samples=2000", "epsilon=0"});
  EXPECT_TRUE(all_finite(no_epsilon));
  // Grazing light and a light of 1e-6 sr.
  for (const std::string& light : {std::string("{type: directional, direction: [1, -0.001, 0], irradiance: 1}"),
                                   std::string("{type: directional, direction: [0.4, -1, 0], irradiance: 1, solid_angle_sr: 0.000001}")}) {
    FrameResult result =
        render(scene_from_yaml(causticbench::testing::pinhole_mirror_sphere("[" + light + "]")), "pinhole", {"samples=500"});
    EXPECT_TRUE(all_finite(result)) << light;
  }
}

TEST(Pinhole, ZeroAreaReflectorIsAClearError) {
  namespace fs = std::filesystem;
  fs::path file = fs::temp_directory_path() / "causticbench_flat_mesh.obj";
  std::ofstream(file) << "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n";  // a degenerate triangle: zero area
  Scene scene = scene_from_yaml("camera: {position: [0, 3, 3], look_at: [0, 0, 0], resolution: [8, 8]}\n"
                                "lights: [{type: directional, direction: [0, -1, 0], irradiance: 1}]\n"
                                "objects:\n  - shape: {type: quad, size: [4, 4]}\n    material: {type: diffuse}\n"
                                "  - shape: {type: mesh, asset: " + file.string() + ", smooth_normals: false}\n"
                                "    material: {type: mirror}\n");
  std::string message = causticbench::testing::input_error_message([&] { render(scene, "pinhole", {"samples=10"}); });
  EXPECT_NE(message.find("reflector of zero area"), std::string::npos) << message;
  fs::remove(file);
}

// The Vulkan backend (lavapipe here) and the CPU backend do the same arithmetic in another order:
// they agree to float rounding (relMSE < 1e-6, flux within 1e-4), for reflection and for refraction.
TEST(PinholeVulkan, AgreesWithTheCpuBackend) {
  Scene mirror = scene_from_yaml(kMirrorSphere);
  Scene water = scene_from_yaml(R"(
camera: {type: orthographic, position: [0, -0.2, 0], look_at: [0, -1, 0], up: [0, 0, 1], view_height: 2, resolution: [24, 24]}
lights: [{type: directional, direction: [0.2, -1, 0.1], irradiance: 1, solid_angle_sr: 0.001}]
objects:
  - shape: {type: quad, size: [4, 4]}
    material: {type: diffuse}
    transform: {translate: [0, -0.5, 0]}
  - shape: {type: water, size: [3, 3], resolution: [64, 64], waves: [{amplitude: 0.02, wavelength: 0.7}, {amplitude: 0.01, wavelength: 0.3, direction_degrees: 60}]}
    material: {type: glass, ior: 1.33}
)");
  struct Case {
    const Scene* scene;
    std::vector<std::string> knobs;
  };
  for (const Case& c : {Case{&mirror, {"samples=3000"}}, Case{&water, {"samples=3000", "interaction=refract"}},
                        Case{&mirror, {"samples=500", "attenuation=false", "fresnel=false"}}}) {
    FrameResult cpu = render(*c.scene, "pinhole", c.knobs);
    std::vector<std::string> vulkan_knobs = c.knobs;
    vulkan_knobs.push_back("backend=vulkan");
    FrameResult vulkan = render(*c.scene, "pinhole", vulkan_knobs);
    double cpu_flux = masked_sum(cpu.caustic, cpu.gbuffer.receiver);
    ASSERT_GT(cpu_flux, 0.0) << c.knobs[0];
    EXPECT_LT(relative_mse(vulkan.caustic, cpu.caustic, cpu.gbuffer.receiver), 1e-6) << c.knobs.back();
    EXPECT_NEAR(masked_sum(vulkan.caustic, cpu.gbuffer.receiver) / cpu_flux, 1.0, 1e-4) << c.knobs.back();
    EXPECT_FALSE(vulkan.method_record["gpu_device"].get<std::string>().empty());
  }
  // Filtered lookups: the CPU backend filters a lat-long texture with OpenImageIO, the Vulkan backend a
  // mip-mapped cube map with textureGrad, so they differ by their filters, not by rounding. Both keep
  // the reference's flux within 4 %. Isotropic filtering agrees closely (measured relMSE 0.0024
  // between the backends, each about 0.003 from the reference). lavapipe's anisotropic cube-map
  // filtering does not: 0.14 from the reference against the CPU's 0.003 (see methods/pinhole/README.md),
  // so only its flux is held to the bound here.
  FrameResult reference = render(mirror, "reference", {"photons_per_pass=400000", "max_passes=40", "target_error=0"});
  double reference_flux = masked_sum(reference.caustic, reference.gbuffer.receiver);
  for (const char* filtering : {"filtering=isotropic", "filtering=anisotropic"}) {
    FrameResult cpu = render(mirror, "pinhole", {"samples=3000", filtering, "filter_implementation=oiio"});
    FrameResult vulkan = render(mirror, "pinhole", {"samples=3000", filtering, "backend=vulkan", "filter_implementation=hardware"});
    EXPECT_NEAR(masked_sum(vulkan.caustic, vulkan.gbuffer.receiver) / reference_flux, 1.0, 0.04) << filtering;
    EXPECT_NEAR(masked_sum(cpu.caustic, cpu.gbuffer.receiver) / reference_flux, 1.0, 0.04) << filtering;
    EXPECT_LT(relative_mse(cpu.caustic, reference.caustic, cpu.gbuffer.receiver), 0.01) << filtering;
    if (std::string(filtering) == "filtering=isotropic") {
      EXPECT_LT(relative_mse(vulkan.caustic, reference.caustic, cpu.gbuffer.receiver), 0.01);
      EXPECT_LT(relative_mse(vulkan.caustic, cpu.caustic, cpu.gbuffer.receiver), 0.01);
    }
  }
}

// The portable path for GPU machines: causticbench dumps a frame, causticbench-gpubench replays it on
// the first Vulkan device, causticbench gpu-compare checks it against the CPU backend's output.
TEST(PinholeVulkan, GpubenchReplaysADumpedFrame) {
  namespace fs = std::filesystem;
  fs::path folder = fs::temp_directory_path() / "causticbench_dump_test";
  fs::remove_all(folder);
  fs::create_directories(folder);
  std::ofstream(folder / "scene.yaml") << kMirrorSphere;
  std::string output;
  std::string dump = (folder / "dump").string();
  int code = causticbench::testing::run_command(std::string(CAUSTICBENCH_BINARY) + " -q render " + (folder / "scene.yaml").string() +
                                                    " --method pinhole --set samples=2000 --out " + (folder / "out").string() +
                                                    " --dump-frame " + dump,
                                                output);
  ASSERT_EQ(code, 0) << output;
  // method.txt names the format that gpubench and gpu-compare read the rest with.
  EXPECT_EQ(read_dump_method(dump), "pinhole");
  std::string method_line;
  std::getline(std::ifstream(dump + "/method.txt"), method_line);
  EXPECT_EQ(method_line, "pinhole");
  code = causticbench::testing::run_command(std::string(CAUSTICBENCH_GPUBENCH) + " " + dump + " --repetitions 2", output);
  ASSERT_EQ(code, 0) << output;
  EXPECT_NE(output.find("evaluations/s"), std::string::npos) << output;
  std::stringstream timings;
  timings << std::ifstream(dump + "/gpu_timings.json").rdbuf();
  EXPECT_NE(timings.str().find("\"method\": \"pinhole\""), std::string::npos) << timings.str();
  EXPECT_NE(timings.str().find("\"isotropic_filtering_honours_gradients\""), std::string::npos) << timings.str();
  code = causticbench::testing::run_command(std::string(CAUSTICBENCH_BINARY) + " gpu-compare " + dump, output);
  EXPECT_EQ(code, 0) << output;
  EXPECT_NE(output.find("pinhole vulkan against cpu"), std::string::npos) << output;
  EXPECT_NE(output.find("): agree"), std::string::npos) << output;  // not "disagree"
  // A dump written before method.txt existed is pinhole's; one without frame.txt either is an input error.
  fs::remove(dump + "/method.txt");
  code = causticbench::testing::run_command(std::string(CAUSTICBENCH_BINARY) + " gpu-compare " + dump, output);
  EXPECT_EQ(code, 0) << output;
  fs::rename(dump + "/frame.txt", dump + "/frame.txt.moved");
  code = causticbench::testing::run_command(std::string(CAUSTICBENCH_BINARY) + " gpu-compare " + dump, output);
  EXPECT_EQ(code, 2) << output;
  EXPECT_NE(output.find("method.txt"), std::string::npos) << output;
  fs::rename(dump + "/frame.txt.moved", dump + "/frame.txt");
  // A corrupted GPU output is caught.
  std::vector<float> wrong = read_floats(dump + "/vulkan_irradiance.bin");
  for (float& value : wrong) value *= 1.01f;
  write_floats(dump + "/vulkan_irradiance.bin", wrong);
  code = causticbench::testing::run_command(std::string(CAUSTICBENCH_BINARY) + " gpu-compare " + dump, output);
  EXPECT_EQ(code, 1) << output;
  // --dump-frame with a method that cannot dump is an input error before any work.
  code = causticbench::testing::run_command(std::string(CAUSTICBENCH_BINARY) + " -q render " + (folder / "scene.yaml").string() +
                                                " --method photon_map --out " + (folder / "out2").string() + " --dump-frame " + dump,
                                            output);
  EXPECT_EQ(code, 2) << output;
  EXPECT_FALSE(fs::exists(folder / "out2"));
  fs::remove_all(folder);
}

// gpubench and gpu-compare trust every listed format's name and tolerances; a folder that is not a dump
// says which file is missing.
TEST(FrameDumps, FormatsAreCompleteAndAFolderWithoutADumpNamesMethodTxt) {
  namespace fs = std::filesystem;
  ASSERT_FALSE(frame_dump_formats().empty());
  for (const FrameDumpFormat& format : frame_dump_formats()) {
    EXPECT_FALSE(format.method.empty());
    EXPECT_GT(format.relmse_tolerance, 0.0) << format.method;
    EXPECT_GT(format.flux_tolerance, 0.0) << format.method;
    EXPECT_EQ(&frame_dump_format(format.method), &format);
  }
  fs::path folder = fs::temp_directory_path() / "causticbench_dump_method_test";
  fs::remove_all(folder);
  fs::create_directories(folder);
  try {
    read_dump_method(folder.string());
    ADD_FAILURE() << "read_dump_method accepted a folder without method.txt or frame.txt";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("method.txt"), std::string::npos) << error.what();
  }
  write_dump_method(folder.string(), "pinhole");
  EXPECT_EQ(read_dump_method(folder.string()), "pinhole");
  fs::remove_all(folder);
}
