// pinhole's unfiltered reflection kernel: its Fresnel throughput tables (methods/pinhole/throughput.h),
// the vector texel fetch against the scalar one, and the shared-exponent light map's precision
// (methods/pinhole/packed_texels.h). Part of test_pinhole (methods/pinhole/CMakeLists.txt).
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include <gtest/gtest.h>

#include "core/image_statistics.h"
#include "core/optics.h"
#include "core/scene.h"
#include "methods/pinhole/light_map.h"
#include "methods/pinhole/packed_texels.h"
#include "methods/pinhole/texel_fetch.h"
#include "methods/pinhole/throughput.h"
#include "tests/test_support.h"

using namespace causticbench;

// The unfiltered kernel's throughput table (methods/pinhole/throughput.h) against the exact Fresnel of
// every specular material of the shipped scenes, with Fresnel on and off: its own measured error is
// below 1e-5, and that measure is honest (random cosines, not on its grid, stay within it).
TEST(PinholeThroughput, TableMatchesTheExactFresnelOfEveryShippedMaterial) {
  size_t materials = 0;
  uint32_t state = 12345;
  auto next = [&] {
    state = state * 1664525u + 1013904223u;
    return static_cast<float>(state >> 8) / static_cast<float>(1u << 24);
  };
  for (const auto& entry : std::filesystem::directory_iterator(CAUSTICBENCH_SCENES)) {
    if (entry.path().extension() != ".yaml") continue;
    Scene scene = load_scene(entry.path().string());
    for (const SceneObject& object : scene.objects) {
      const Material& material = object.material;
      if (material.kind != MaterialKind::mirror && material.kind != MaterialKind::glass &&
          material.kind != MaterialKind::diffuse_mirror)
        continue;
      ++materials;
      for (bool fresnel : {true, false}) {
        ThroughputTable table(material, fresnel);
        const std::string where = entry.path().filename().string() + " " + object.name + (fresnel ? "" : " no fresnel");
        EXPECT_LT(table.max_error(), 1e-5f) << where;
        for (int i = 0; i < 2000; ++i) {
          float cosine = next();
          Color exact = light_throughput(material, Interaction{false, fresnel}, cosine);
          Color tabled = table(cosine);
          float error = std::max({std::abs(exact.r - tabled.r), std::abs(exact.g - tabled.g), std::abs(exact.b - tabled.b)});
          ASSERT_LE(error, table.max_error() * 1.01f + 1e-7f) << where << " at cos " << cosine;
        }
        EXPECT_EQ(table(1.0f).r, light_throughput(material, Interaction{false, fresnel}, 1.0f).r) << where;
      }
    }
  }
  EXPECT_GE(materials, 5u) << "the shipped scenes' metals and glass";
}

// The vector fetch (texel_fetch.h) against the scalar one under an environment map, where every
// sample-pixel pair fetches: the vector fetch reads the shared-exponent copy of the map (packed_texels.h,
// each channel within 2^-9 of its texel's largest), the scalar one the float map, so the images differ
// by that rounding, which averages out over the samples of a pixel: measured relMSE 4e-8 and 5e-8, flux
// 1.5e-5 and 2.1e-5.
TEST(PinholeThroughput, VectorFetchAgreesWithTheScalarFetch) {
  if (!vector_fetch_enabled()) GTEST_SKIP() << "no AVX2 here (or CAUSTICBENCH_PINHOLE_SCALAR_FETCH is set)";
  const std::string path = std::string(CAUSTICBENCH_SCENES) + "/ring_forest.yaml";
  std::ifstream file(path);
  std::stringstream text;
  text << file.rdbuf();
  // The ring alone (one Fresnel table), and with a glass ball inside it (two tables, per lane).
  const std::string ball = "\n  - name: ball\n    shape: {type: sphere, radius: 0.25}\n    transform: {translate: [0.0, 0.3, 0.0]}\n"
                           "    material: {type: glass, ior: 1.5}\n";
  for (const std::string& extra : {std::string(), ball}) {
    Scene scene = load_scene_from_string(text.str() + extra, "ring_forest.yaml", CAUSTICBENCH_SCENES);
    set_resolution(scene, 48, 36);
    // The unfiltered reflection kernel, the glass ball reflecting (its Fresnel table beside the ring's).
    const std::vector<std::string> knobs = {"samples=300", "environment_resolution=64", "filtering=none",
                                            "interaction=reflect"};
    FrameResult vector = causticbench::testing::render(scene, "pinhole", knobs);
    ::setenv("CAUSTICBENCH_PINHOLE_SCALAR_FETCH", "1", 1);
    FrameResult scalar = causticbench::testing::render(scene, "pinhole", knobs);
    ::unsetenv("CAUSTICBENCH_PINHOLE_SCALAR_FETCH");
    const std::string where = extra.empty() ? "ring" : "ring and ball";
    const double packed_error = vector.method_record["packed_texels_max_error"].get<double>();
    EXPECT_GT(packed_error, 0.0) << "an environment map is read packed; " << where;
    EXPECT_LE(packed_error, std::ldexp(1.0, -9)) << where;
    const double flux = masked_sum(scalar.caustic, scalar.gbuffer.receiver);
    ASSERT_GT(flux, 0.0) << where;
    EXPECT_NEAR(masked_sum(vector.caustic, vector.gbuffer.receiver) / flux, 1.0, 1e-4) << where;
    EXPECT_LT(relative_mse(vector.caustic, scalar.caustic, scalar.gbuffer.receiver), 1e-6) << where;
  }
}

// The shared-exponent map (packed_texels.h): every channel of every texel within max(2^-9 x its texel's
// largest channel, 2^-40 x the map's largest) over 50 binades of radiance, that is, within 2^-9 for
// texels down to 2^-31 of the brightest; zero stays zero; the brightest texel keeps its value to 0.2 %.
TEST(PinholeThroughput, PackedTexelsKeepEveryChannelWithinTheirStatedPrecision) {
  std::vector<float> rgb;
  uint32_t state = 777;
  auto next = [&] {
    state = state * 1664525u + 1013904223u;
    return static_cast<double>(state >> 8) / static_cast<double>(1u << 24);
  };
  for (int i = 0; i < 30000; ++i) {
    const double magnitude = std::ldexp(1.0, static_cast<int>(next() * 50.0) - 28);
    for (int c = 0; c < 3; ++c) rgb.push_back(static_cast<float>(magnitude * next() * (c == 2 && i % 3 == 0 ? 0.0 : 1.0)));
  }
  rgb.insert(rgb.end(), {0.0f, 0.0f, 0.0f, 3.0e7f, 1.0f, 0.0f});
  const double map_largest = 3.0e7;
  PackedTexels packed(rgb);
  ASSERT_EQ(packed.texels().size(), rgb.size() / 3);
  double worst = 0.0;
  size_t full_precision = 0;
  for (size_t i = 0; i < packed.texels().size(); ++i) {
    const Color decoded = packed.decode(packed.texels()[i]);
    const double largest = std::max({rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2]});
    const double bound = std::max(std::ldexp(largest, -9), std::ldexp(map_largest, -40));
    full_precision += largest >= std::ldexp(map_largest, -31);
    for (int c = 0; c < 3; ++c) {
      const double error = std::abs(static_cast<double>(decoded[c]) - rgb[3 * i + c]);
      if (largest == 0.0) {
        ASSERT_EQ(decoded[c], 0.0f) << i;
      }
      ASSERT_LE(error, bound) << "texel " << i << " channel " << c << " of " << rgb[3 * i + c];
      if (largest >= std::ldexp(map_largest, -31)) worst = std::max(worst, error / largest);
    }
  }
  EXPECT_GT(full_precision, 10000u);
  EXPECT_LE(packed.max_relative_error(), std::ldexp(1.0, -9));
  EXPECT_GT(worst, std::ldexp(1.0, -11)) << "9-bit mantissas round visibly";
  EXPECT_GE(packed.max_relative_error(), worst * 0.999);
  EXPECT_NEAR(packed.decode(packed.texels().back()).r / map_largest, 1.0, 2e-3);
}
