// prt against the reference: the glass sphere under an environment that is dark but for a smooth lobe
// (a Gaussian spot of 0.5 sr), at stated knobs.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "core/image.h"
#include "core/image_statistics.h"
#include "tests/test_support.h"

namespace causticbench {
namespace {

using causticbench::testing::kSmallGlassSphere;
using causticbench::testing::kSmallSceneReferenceKnobs;
using causticbench::testing::render;
using causticbench::testing::scene_from_yaml;

std::string under_a_lobe() {
  std::string text = kSmallGlassSphere;
  const std::string sun = "lights: [{type: directional, direction: [0.3, -1, 0.2], irradiance: 1}]";
  text.replace(text.find(sun), sun.size(),
               "lights: [{type: environment, procedural: gaussian_spot, direction: [0.3, -1, 0.2], irradiance: 1, "
               "solid_angle_sr: 0.5}]");
  return text;
}

struct Comparison {
  double relmse, energy;
};

Comparison against_reference(const Scene& scene, const std::vector<std::string>& knobs, const FrameResult& reference) {
  const FrameResult result = render(scene, "prt", knobs);
  const std::vector<uint8_t>& receivers = reference.gbuffer.receiver;
  return {relative_mse(result.caustic, reference.caustic, receivers),
          masked_sum(result.caustic, receivers) / masked_sum(reference.caustic, receivers)};
}

// Measured (seed 1): relMSE 0.139, energy 1.001 at these knobs (the grid's cells, 0.1 across, and the
// photons' noise); the bounds leave room for the noise of another platform's rounding.
TEST(Prt, SmoothLobeOnTheGlassSphereMatchesTheReference) {
  const Scene scene = scene_from_yaml(under_a_lobe());
  const FrameResult reference = render(scene, "reference", kSmallSceneReferenceKnobs);
  const Comparison measured = against_reference(
      scene, {"sh_order=5", "grid_resolution=32", "volume_radius=4", "source_directions=128", "photons_per_direction=10000"},
      reference);
  std::printf("glass sphere under a 0.5 sr lobe: relMSE %.4f, energy %.4f\n", measured.relmse, measured.energy);
  EXPECT_LT(measured.relmse, 0.2);
  EXPECT_NEAR(measured.energy, 1.0, 0.05);
}

// precision: float16 stores the matrices in half floats: the image is float32's to half precision, and a
// float16 build stored in the build cache and loaded again renders the same bits and measures the same
// band-limit loss.
TEST(Prt, Float16MatricesAgreeWithFloat32AndReloadBitIdentically) {
  const Scene scene = scene_from_yaml(kSmallGlassSphere);
  // 50 directions resolve the band limit's loss to 5 bands (band_limit.h), which the reload must keep too.
  const std::vector<std::string> knobs = {"sh_order=4", "grid_resolution=16", "volume_radius=4", "source_directions=50",
                                          "photons_per_direction=2560"};
  std::vector<std::string> half = knobs;
  half.push_back("precision=float16");
  const FrameResult full = render(scene, "prt", knobs), halved = render(scene, "prt", half);
  const std::vector<uint8_t>& receivers = full.gbuffer.receiver;
  const double relmse = relative_mse(halved.caustic, full.caustic, receivers);
  const double energy = masked_sum(halved.caustic, receivers) / masked_sum(full.caustic, receivers);
  std::printf("float16 against float32: relMSE %.3g, energy %.6f, memory %zu against %zu bytes\n", relmse, energy,
              halved.memory_bytes, full.memory_bytes);
  EXPECT_GT(relmse, 0.0) << "the halves were used";
  EXPECT_LT(relmse, 1e-5);
  EXPECT_NEAR(energy, 1.0, 1e-3);
  EXPECT_LT(static_cast<double>(halved.memory_bytes), 0.55 * static_cast<double>(full.memory_bytes));

  const causticbench::testing::TemporaryFolder folder("prt_float16_build");
  std::ofstream(folder.path("scene.yaml")) << kSmallGlassSphere;
  std::string command = std::string(CAUSTICBENCH_BINARY) + " -q render " + folder.path("scene.yaml") +
                        " --method prt --build-cache " + folder.path("builds");
  for (const std::string& knob : half) command += " --set " + knob;
  std::string output;
  ASSERT_EQ(causticbench::testing::run_command(command + " --out " + folder.path("computed"), output), 0) << output;
  ASSERT_EQ(causticbench::testing::run_command(command + " --out " + folder.path("loaded"), output), 0) << output;
  std::stringstream record;
  record << std::ifstream(folder.path("loaded") + "/record.json").rdbuf();
  EXPECT_NE(record.str().find("\"source\": \"loaded\""), std::string::npos) << "the second run loads the build";
  const Image computed = read_exr(folder.path("computed") + "/caustic.exr");
  const Image loaded = read_exr(folder.path("loaded") + "/caustic.exr");
  ASSERT_EQ(computed.pixel_count(), loaded.pixel_count());
  size_t different = 0;
  for (size_t pixel = 0; pixel < computed.pixel_count(); ++pixel)
    for (int c = 0; c < 3; ++c) different += computed.at(pixel, c) != loaded.at(pixel, c);
  EXPECT_EQ(different, 0u);
  auto band_limit = [&](const std::string& run) {
    const nlohmann::json record = nlohmann::json::parse(std::ifstream(folder.path(run) + "/record.json"));
    return record.at("method_record").at("objects")[0].at("band_limit");
  };
  EXPECT_GT(band_limit("computed").at("full_fluence").get<double>(), 0.0);
  EXPECT_EQ(band_limit("computed"), band_limit("loaded"));
}

}  // namespace
}  // namespace causticbench
