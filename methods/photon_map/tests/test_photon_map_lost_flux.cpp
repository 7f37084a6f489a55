// photon_map's lost flux (CausticMethod::lost_flux): the flux of the photons in view farther than
// max_radius from every receiver pixel's point, against a brute-force count over every photon and every
// receiver pixel (issue 32).
#include <algorithm>
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "core/photon_tracer.h"
#include "core/scene.h"
#include "core/tracer.h"
#include "methods/common/photon_view.h"
#include "tests/test_support.h"

using namespace causticbench;
using causticbench::testing::render;
using causticbench::testing::scene_from_yaml;

namespace {

// The small glass sphere at 24 x 24: few pixels, so that pixel points lie far apart on the floor.
Scene small_scene() {
  return scene_from_yaml(causticbench::testing::replace_once(causticbench::testing::kSmallGlassSphere,
                                                             "resolution: [40, 40]", "resolution: [24, 24]"));
}

// The fraction of the in-view flux farther than max_radius from every receiver pixel's point, by brute
// force over the same photons the method traces (its seed, its count).
double brute_force_lost(const Scene& scene, const GBuffer& gbuffer, uint64_t count, double max_radius) {
  const SceneFrame frame(scene, 0.0);
  const Tracer tracer(frame);
  std::vector<Photon> photons;
  PhotonStats stats;
  CausticPhotonTracer(tracer, PhotonTracerSettings{1}).trace(0, count, photons, stats);
  double total = 0.0, missed = 0.0;
  for (const Photon& photon : photons) {
    std::optional<CameraFrame::ImagePoint> image = photon_seen_by_camera(frame.camera, tracer, photon);
    if (!image || !gbuffer.receiver[static_cast<size_t>(image->y) * gbuffer.width + image->x]) continue;
    double nearest = 1e30;
    for (size_t pixel = 0; pixel < gbuffer.pixel_count(); ++pixel)
      if (gbuffer.receiver[pixel]) nearest = std::min(nearest, static_cast<double>(glm::length(photon.position - gbuffer.position[pixel])));
    total += luminance(photon.power);
    if (nearest > max_radius) missed += luminance(photon.power);
  }
  return missed / total;
}

}  // namespace

// max_radius above the pixel spacing: every photon in view lies within it of some pixel point, exactly 0
// lost (whatever k; k 4 leaves photons between the gathers, which is not lost light). max_radius 0.01 on
// a floor whose pixel points lie about 0.1 apart: most of the light lies beyond the cap, and the count
// agrees with the brute force (to one photon of about a thousand in view, for rounding at the cap).
TEST(PhotonMapLostFlux, NothingLostWithinTheCapAndTheBruteForceCountBeyondIt) {
  const Scene scene = small_scene();
  const FrameResult wide = render(scene, "photon_map", {"photons=4000", "k=4", "max_radius=0.5"});
  ASSERT_TRUE(wide.lost_flux.has_value());
  EXPECT_EQ(wide.lost_flux->fraction, 0.0);
  const FrameResult narrow = render(scene, "photon_map", {"photons=4000", "k=4", "max_radius=0.01"});
  ASSERT_TRUE(narrow.lost_flux.has_value());
  const double expected = brute_force_lost(scene, narrow.gbuffer, 4000, 0.01);
  std::printf("max_radius 0.01: lost %.4f, brute force %.4f (%s)\n", narrow.lost_flux->fraction, expected,
              narrow.lost_flux->advice.c_str());
  EXPECT_GT(expected, 0.5);
  EXPECT_NEAR(narrow.lost_flux->fraction, expected, 2e-3);
  EXPECT_EQ(narrow.lost_flux->knob, "max_radius");
}
