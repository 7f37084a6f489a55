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

namespace {

// kSmallGlassSphere with every length multiplied by 100 (the scene in centimetres): the camera, the
// floor, the sphere and where it stands. A directional light's irradiance is per unit area, so E_c on
// the floor is the same pattern at the same values, a hundred times larger.
Scene small_scene_in_centimetres() {
  return scene_from_yaml(R"(
camera: {position: [0, 200.0, 200.0], look_at: [0, 10.0, 0], fov_degrees: 35, resolution: [40, 40]}
lights: [{type: directional, direction: [0.3, -1, 0.2], irradiance: 1}]
objects:
  - shape: {type: quad, size: [600, 600]}
    material: {type: diffuse, albedo: 0.8}
  - shape: {type: sphere, radius: 40}
    material: {type: glass, ior: 1.5}
    transform: {translate: [0, 60, 0]}
)");
}

double total_luminance(const Image& image) {
  double sum = 0.0;
  for (size_t pixel = 0; pixel < image.pixel_count(); ++pixel) sum += luminance(image.rgb(pixel));
  return sum;
}

}  // namespace

// The default `max_radius: auto` caps the gather at 8 footprints of each pixel, so the estimate does not
// depend on the scene's units: the scene in metres and in centimetres give the same image (the same
// photons by seed, scaled; the summed E_c agrees to 1e-5, the bound allows 1e-3 for rounding at a cap), nothing is
// lost in either, and the record states the caps in scene units, a hundred times larger in centimetres.
// A fixed max_radius of 0.1 is 6 footprints in metres and a twentieth of one in centimetres, where most
// of the light falls between the caps (the defect the auto default fixes).
TEST(PhotonMapLostFlux, AutoRadiusFollowsThePixelsWhateverTheSceneUnits) {
  const Scene metres = scene_from_yaml(causticbench::testing::kSmallGlassSphere);
  const Scene centimetres = small_scene_in_centimetres();
  const FrameResult in_metres = render(metres, "photon_map", {"photons=20000"});
  const FrameResult in_centimetres = render(centimetres, "photon_map", {"photons=20000"});
  ASSERT_TRUE(in_metres.lost_flux && in_centimetres.lost_flux);
  EXPECT_EQ(in_metres.lost_flux->fraction, 0.0);
  EXPECT_EQ(in_centimetres.lost_flux->fraction, 0.0);
  const double sum_metres = total_luminance(in_metres.caustic);
  const double sum_centimetres = total_luminance(in_centimetres.caustic);
  ASSERT_GT(sum_metres, 0.0);
  EXPECT_NEAR(sum_centimetres / sum_metres, 1.0, 1e-3);
  const double median_metres = in_metres.method_record.at("max_radius_used").at("median").get<double>();
  const double median_centimetres = in_centimetres.method_record.at("max_radius_used").at("median").get<double>();
  EXPECT_NEAR(median_centimetres / median_metres, 100.0, 1.0);
  std::printf("auto cap: median %.4g m, %.4g cm; summed E_c %.6g and %.6g\n", median_metres, median_centimetres,
              sum_metres, sum_centimetres);

  const FrameResult fixed = render(centimetres, "photon_map", {"photons=20000", "max_radius=0.1"});
  ASSERT_TRUE(fixed.lost_flux);
  std::printf("max_radius 0.1 in centimetres: lost %.3f\n", fixed.lost_flux->fraction);
  EXPECT_GT(fixed.lost_flux->fraction, 0.5);
  EXPECT_EQ(fixed.method_record.count("max_radius_used"), 0u);
}
