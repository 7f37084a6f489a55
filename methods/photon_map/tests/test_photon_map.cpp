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
  EXPECT_LT(errors[1], errors[0]);
  EXPECT_LT(errors[2], errors[1]);
  EXPECT_LT(errors[2], 0.05) << "relMSE at 1M photons";
  // Total caustic flux seen by the camera agrees within 10% at 1M photons (measured: 4% low at 10k
  // photons, 6% low at 1M; see the photon_map README's open questions).
  EXPECT_NEAR(energy[2], 1.0, 0.10);
}
