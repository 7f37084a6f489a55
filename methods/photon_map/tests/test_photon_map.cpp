// The photon map converges to the reference as photons grow.
#include <gtest/gtest.h>

#include "core/image_statistics.h"
#include "tests/test_support.h"

using namespace causticbench;
using causticbench::testing::render;
using causticbench::testing::scene_from_yaml;

TEST(PhotonMap, ConvergesToTheReference) {
  Scene scene = scene_from_yaml(causticbench::testing::kSmallGlassSphere);
  FrameResult reference = render(scene, "reference", {"photons_per_pass=400000", "max_passes=60", "target_error=0"});
  std::vector<double> errors, energy;
  // A consistent density estimate needs k to grow with the photon count (variance ~ 1/k) while the
  // radius shrinks (bias): k ~ sqrt(photons).
  for (auto [photons, k] : {std::pair{10000, 20}, std::pair{100000, 63}, std::pair{1000000, 200}}) {
    FrameResult run = render(scene, "photon_map", {"photons=" + std::to_string(photons), "k=" + std::to_string(k),
                                                   "max_radius=0.5"});
    errors.push_back(relative_mse(run.caustic, reference.caustic, run.gbuffer.receiver));
    energy.push_back(masked_sum(run.caustic, run.gbuffer.receiver) / masked_sum(reference.caustic, run.gbuffer.receiver));
  }
  for (size_t i = 0; i < errors.size(); ++i) std::printf("run %zu: relMSE %.4f, energy %.4f\n", i, errors[i], energy[i]);
  EXPECT_LT(errors[1], errors[0]);
  EXPECT_LT(errors[2], errors[1]);
  // Measured against this reference (the footprint tally, 24 M photons): relMSE 0.0307, 0.0110, 0.0043
  // and energy 1.040, 0.973, 0.997 at 10k, 100k and 1M photons. relMSE at 1M is bounded at 1.5 times its
  // value, the energy in view within 2 % (nothing is lost: max_radius 0.5 reaches every photon in view).
  // The "6 % low at 1M" once quoted here was against progressive photon mapping, whose radius bias had
  // added about 6 % to the reference's sum on this sphere (lpi's environment test measured the same).
  EXPECT_LT(errors[2], 1.5 * 0.0043) << "relMSE at 1M photons";
  EXPECT_NEAR(energy[2], 1.0, 0.02);
}
