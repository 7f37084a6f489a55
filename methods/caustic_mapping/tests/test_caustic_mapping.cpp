// caustic_mapping (Shah et al. 2007): analytic answers on a flat mirror, the image-space search against
// exact rays on a flat floor and where it must fail, and the glass sphere's flux against the reference
// with the lost-flux counter closing the balance.
#include <cmath>
#include <cstdio>
#include <string>

#include <gtest/gtest.h>

#include "core/image_statistics.h"
#include "core/scene.h"
#include "core/tracer.h"
#include "methods/caustic_mapping/pass_parts.h"
#include "tests/test_support.h"

using namespace causticbench;
using causticbench::testing::render;
using causticbench::testing::scene_from_yaml;
using causticbench::testing::kFlatMirror;
using causticbench::testing::kBeamIrradiance;
using causticbench::testing::kBeamHalfX;
using causticbench::testing::kBeamHalfZ;

// Every photon of the flat mirror lands (the floor is flat and the light sees it: the search converges),
// so nothing is lost, the flux the pixels integrate is the beam's flux, and inside the beam E_c is the
// reflected irradiance: for every splat kernel. The pixels' sum is the photons' flux to 1 % (the lookup's
// bilinear reads at the beam's edge), and the photons' flux the beam's to 2 % (the photon buffer's covered
// texels give the mirror's cross-section to 1.4 % at 256^2); the interior mean to 2 % with gaussian and variable splats,
// to 10 % with point splats, whose one texel per photon aliases against the photons' grid (3 or 2 photons
// a texel: rows 15 % apart over the few interior pixels).
TEST(CausticMapping, FlatMirrorConservesFluxAndGivesTheReflectedBeamForEverySplat) {
  const Scene scene = scene_from_yaml(kFlatMirror);
  for (const char* splat : {"splat=point", "splat=gaussian", "splat=variable"}) {
    const FrameResult result = render(scene, "caustic_mapping", {splat, "photon_resolution=256", "caustic_map_resolution=256"});
    ASSERT_TRUE(result.lost_flux);
    EXPECT_EQ(result.lost_flux->fraction, 0.0) << splat;
    double flux = 0.0, interior = 0.0;
    int interior_pixels = 0;
    for (size_t pixel = 0; pixel < result.gbuffer.pixel_count(); ++pixel) {
      if (!result.gbuffer.receiver[pixel]) continue;
      const double value = luminance(result.caustic.rgb(pixel));
      flux += value * result.gbuffer.footprint[pixel] * result.gbuffer.footprint[pixel];
      const Vec3 p = result.gbuffer.position[pixel];
      if (std::abs(p.x - 1.5) < kBeamHalfX - 0.04 && std::abs(p.z) < kBeamHalfZ - 0.04) {
        interior += value;
        ++interior_pixels;
      }
    }
    const double beam_flux = kBeamIrradiance * 4.0 * kBeamHalfX * kBeamHalfZ;
    // The photons' flux: the photon buffer's covered texels times a texel's area across the light.
    const nlohmann::json& pass = result.method_record.at("passes").at(0);
    const double texel_side = 2.0 * pass.at("photon_buffer_half_extent").get<double>() / 256.0;
    const double photon_flux = kBeamIrradiance * pass.at("photons").get<double>() * texel_side * texel_side;
    std::printf("%s: flux %.4f (photons %.4f, beam %.4f), interior mean %.4f over %d pixels\n", splat, flux,
                photon_flux, beam_flux, interior / interior_pixels, interior_pixels);
    ASSERT_GT(interior_pixels, 20);
    EXPECT_NEAR(flux / photon_flux, 1.0, 0.01) << splat;
    EXPECT_NEAR(photon_flux / beam_flux, 1.0, 0.02) << splat;
    EXPECT_NEAR(interior / interior_pixels / kBeamIrradiance, 1.0, std::string(splat) == "splat=point" ? 0.1 : 0.02)
        << splat;
  }
}

namespace {

// A floor under a vertical sun with a diffuse table (a 1 x 1 top, 0.5 above the floor) beside the
// middle: the light sees the floor and the table's top, not the floor under the table.
const char* const kFloorAndTable = R"(
camera: {type: orthographic, position: [0, 5, 0], look_at: [0, 0, 0], up: [0, 0, 1], view_height: 4, resolution: [16, 16]}
lights: [{type: directional, direction: [0, -1, 0], irradiance: 1}]
objects:
  - shape: {type: quad, size: [4, 4]}
    material: {type: diffuse, albedo: 0.8}
  - shape: {type: quad, size: [1, 1]}
    material: {type: diffuse, albedo: 0.8}
    transform: {translate: [1.2, 0.5, 0]}
)";

}  // namespace

// The paper's search on a flat floor seen by the light: from the receiver under the photon, each step
// d <- |q(p + d r) - p| contracts the error by sin^2 of the ray's angle to the light, so rays within 30
// degrees of it meet the exact hit within two texels after 5 steps (0.25^5 of a start 15 % off). A ray
// that leaves the light's view, and one that passes under the table, where the light sees the table's
// top and not the floor the ray meets, are counted as failures, never returned as a hit.
TEST(CausticMapping, ImageSpaceSearchConvergesOnAFlatFloorAndFailsWhereItCannot) {
  const Scene scene = scene_from_yaml(kFloorAndTable);
  const SceneFrame frame(scene, 0.0);
  const Tracer tracer(frame);
  const LightView view = LightView::orthographic(Vec3(0, -1, 0), Vec3(0, 0, 0), 2.0);
  const int n = 256;
  const caustic_mapping::ReceiverMap map = caustic_mapping::render_receiver_map(tracer, view, n, 10.0);
  const double texel = 4.0 / n;
  int checked = 0;
  for (double angle : {0.0, 10.0, 20.0, 30.0}) {
    for (double azimuth : {0.0, 2.0, 4.0}) {
      const double a = angle * kPiDouble / 180.0;
      const Vec3 direction(static_cast<float>(std::sin(a) * std::cos(azimuth)), static_cast<float>(-std::cos(a)),
                           static_cast<float>(std::sin(a) * std::sin(azimuth)));
      const Vec3 origin(-0.6f, 1.5f, -0.3f);
      const caustic_mapping::SearchResult image = caustic_mapping::search_receiver(map, tracer, origin, direction, 5, false);
      const caustic_mapping::SearchResult exact = caustic_mapping::search_receiver(map, tracer, origin, direction, 0, true);
      ASSERT_EQ(image.failure, caustic_mapping::SearchFailure::none) << angle << " " << azimuth;
      ASSERT_EQ(exact.failure, caustic_mapping::SearchFailure::none);
      EXPECT_LT(glm::length(image.hit - exact.hit), 2.0 * texel) << angle << " " << azimuth;
      ++checked;
    }
  }
  EXPECT_EQ(checked, 12);
  // Upwards: the ray never meets the receivers the light sees.
  const caustic_mapping::SearchResult up =
      caustic_mapping::search_receiver(map, tracer, Vec3(0, 1, 0), glm::normalize(Vec3(0.2f, 1.0f, 0.0f)), 5, false);
  EXPECT_NE(up.failure, caustic_mapping::SearchFailure::none);
  // Out of the window: a ray towards the floor beyond the map's edge.
  const caustic_mapping::SearchResult away =
      caustic_mapping::search_receiver(map, tracer, Vec3(1.9f, 1.0f, 0), glm::normalize(Vec3(1.0f, -0.3f, 0.0f)), 5, false);
  EXPECT_EQ(away.failure, caustic_mapping::SearchFailure::left_view);
  // Under the table: from beside it, shallow, so that the ray passes below the top (y 0.5) to the floor
  // beneath it; the light sees the top there. Exact: the floor under the table.
  const Vec3 origin(0.4f, 0.3f, 0.0f), under = glm::normalize(Vec3(1.0f, -0.35f, 0.0f));
  const caustic_mapping::SearchResult exact = caustic_mapping::search_receiver(map, tracer, origin, under, 0, true);
  ASSERT_EQ(exact.failure, caustic_mapping::SearchFailure::none);
  EXPECT_NEAR(exact.hit.y, 0.0f, 1e-3f);
  EXPECT_GT(exact.hit.x, 0.7f);
  const caustic_mapping::SearchResult image = caustic_mapping::search_receiver(map, tracer, origin, under, 5, false);
  EXPECT_EQ(image.failure, caustic_mapping::SearchFailure::not_converged);
}

// The glass sphere at default knobs against the reference: Wyman's two-interface approximation finds no
// way out for the rays near the silhouette (total internal reflection at the estimated exit), which the
// lost-flux counter counts. What lands plus what is lost is the reference's flux in view: the counter is
// an independent account of the missing energy (measured: 0.749 + 0.236 and, exact intersection,
// 0.786 + 0.205 at 256 x 256, 512^2 photons), within 6 % here at 64 x 64 (the reference's Fresnel-reflected light, which
// the method does not follow, is part of the gap).
TEST(CausticMapping, GlassSphereFluxPlusLostFluxIsTheReferenceFlux) {
  const Scene scene = scene_from_yaml(causticbench::testing::kSmallGlassSphere);
  const FrameResult reference = render(scene, "reference", causticbench::testing::kSmallSceneReferenceKnobs);
  const FrameResult result = render(scene, "caustic_mapping", {});
  ASSERT_TRUE(result.lost_flux);
  const double energy = masked_sum(result.caustic, result.gbuffer.receiver) / masked_sum(reference.caustic, reference.gbuffer.receiver);
  std::printf("energy %.3f, lost %.3f, sum %.3f\n", energy, result.lost_flux->fraction, energy + result.lost_flux->fraction);
  EXPECT_GT(result.lost_flux->fraction, 0.05);
  EXPECT_NEAR(energy + result.lost_flux->fraction, 1.0, 0.06);
}

namespace {

// The second moment of E_c about its peak, over the receiver pixels within `window` of the peak, in
// scene units: how wide the focus is.
double focus_width(const FrameResult& result, double window) {
  size_t peak = 0;
  double best = -1.0;
  for (size_t pixel = 0; pixel < result.gbuffer.pixel_count(); ++pixel)
    if (result.gbuffer.receiver[pixel] && luminance(result.caustic.rgb(pixel)) > best) {
      best = luminance(result.caustic.rgb(pixel));
      peak = pixel;
    }
  const Vec3 centre = result.gbuffer.position[peak];
  double weight = 0.0, moment = 0.0;
  for (size_t pixel = 0; pixel < result.gbuffer.pixel_count(); ++pixel) {
    if (!result.gbuffer.receiver[pixel]) continue;
    const double distance = glm::length(result.gbuffer.position[pixel] - centre);
    if (distance > window) continue;
    const double value = luminance(result.caustic.rgb(pixel));
    weight += value;
    moment += value * distance * distance;
  }
  return std::sqrt(moment / weight);
}

}  // namespace

// Wyman & Dachsbacher's variable splats against fixed ones at equal photons on the glass sphere's focus
// (96 x 96, caustic map 256^2): less error than a one-texel or a fixed Gaussian splat at 32^2 and 64^2
// photons (measured relMSE: 1.42 / 0.58 / 0.30 and 0.55 / 0.40 / 0.34 for point / gaussian / variable;
// the floor of about 0.3 is the light the two-interface approximation loses), and the focus no wider
// than the reference's (the second moment of E_c within 0.3 of the peak: 0.107 at both, the reference's
// 0.110) nor than the fixed Gaussian's beyond the 5 % that the photon grid's alignment with the map
// moves either (0.105 and 0.109 for the Gaussian). The method is deterministic: no seed.
TEST(CausticMapping, VariableSplatsHaveLessErrorThanFixedOnesAndNoWiderFocus) {
  const Scene scene = scene_from_yaml(causticbench::testing::replace_once(causticbench::testing::kSmallGlassSphere,
                                                                         "resolution: [40, 40]", "resolution: [96, 96]"));
  const FrameResult reference = render(scene, "reference", causticbench::testing::kSmallSceneReferenceKnobs);
  const double reference_width = focus_width(reference, 0.3);
  for (const char* photons : {"photon_resolution=32", "photon_resolution=64"}) {
    double error[3] = {}, width[3] = {};
    int kernel = 0;
    for (const char* splat : {"splat=point", "splat=gaussian", "splat=variable"}) {
      const FrameResult result = render(scene, "caustic_mapping", {photons, splat, "caustic_map_resolution=256"});
      error[kernel] = relative_mse(result.caustic, reference.caustic, reference.gbuffer.receiver);
      width[kernel] = focus_width(result, 0.3);
      std::printf("%s %s: relMSE %.4f, focus width %.4f\n", photons, splat, error[kernel], width[kernel]);
      ++kernel;
    }
    EXPECT_LT(error[2], error[0]) << photons;
    EXPECT_LT(error[2], error[1]) << photons;
    EXPECT_LE(width[2], reference_width * 1.02) << photons;
    EXPECT_LE(width[2], width[1] * 1.05) << photons;
  }
}

// Issue 52, item 6: a sun 3 degrees above the floor, off a mirror dish tilted to throw it down. The search
// starts at the receiver the light sees behind the photon's own texel; at 3 degrees the light sees past
// the dish to no receiver at all (the floor ends long before the sun's ray through the dish, 1.2 high,
// meets y = 0 at 23 m), so every search fails at its start and more iterations cannot help: the advice
// names intersection: exact, and following it lands every photon, while 20 iterations change nothing.
// The advice it gave before ("raise search_iterations") recovered nothing.
TEST(CausticMapping, AGrazingSunDefeatsTheSearchAtItsStartAndTheAdviceNamesTheExactIntersection) {
  const Scene scene = scene_from_yaml(R"(name: grazing_dish
camera: {position: [2.5, 2.0, 2.5], look_at: [0.0, 0.3, 0.0], fov_degrees: 40, resolution: [48, 48]}
lights:
  - {name: sun, type: directional, direction: [0.9986295, -0.0523360, 0.0], irradiance: 3.0}
objects:
  - {name: floor, shape: {type: quad, size: [6.0, 6.0]}, material: {type: diffuse, albedo: 0.75}}
  - name: dish
    shape: {type: paraboloid, focal_length: 0.5, radius: 0.5}
    transform: {translate: [0.0, 1.2, 0.0], rotate: [0.0, 0.0, 134.0]}
    material: {type: mirror, reflectance: 0.95}
)");
  const std::vector<std::string> few = {"photon_resolution=128", "caustic_map_resolution=128"};
  auto with = [&](std::vector<std::string> knobs) {
    knobs.insert(knobs.end(), few.begin(), few.end());
    return render(scene, "caustic_mapping", knobs);
  };
  const FrameResult defaults = with({});
  ASSERT_TRUE(defaults.lost_flux);
  const nlohmann::json& pass = defaults.method_record["passes"][0];
  std::printf("defaults: lost %.3f, %s of %s searches failed, %s at their start; advice: %s\n",
              defaults.lost_flux->fraction, pass["search_failed"].dump().c_str(), pass["photons"].dump().c_str(),
              pass["search_failed_at_start"].dump().c_str(), defaults.lost_flux->advice.c_str());
  EXPECT_GT(defaults.lost_flux->fraction, 0.99);
  EXPECT_EQ(pass["search_failed_at_start"], pass["search_failed"]);
  EXPECT_EQ(defaults.lost_flux->knob, "intersection");
  EXPECT_NE(defaults.lost_flux->advice.find("set intersection: exact"), std::string::npos);
  const FrameResult more = with({"search_iterations=20"});
  EXPECT_GT(more.lost_flux->fraction, 0.99) << "more iterations: nothing recovered";
  const FrameResult exact = with({"intersection=exact"});
  std::printf("search_iterations 20: lost %.3f; intersection exact: lost %.3f, E_c sum %.3g\n", more.lost_flux->fraction,
              exact.lost_flux->fraction, masked_sum(exact.caustic, exact.gbuffer.receiver));
  EXPECT_LT(exact.lost_flux->fraction, 0.01) << "the advice followed recovers the light";
  EXPECT_GT(masked_sum(exact.caustic, exact.gbuffer.receiver), 0.0);
  EXPECT_EQ(exact.method_record["passes"][0]["search_failed_at_start"], 0) << "an exact ray is no search";
  // A search of 0 iterations that starts but does not converge read once too: it had a start. On the flat
  // mirror's beam, steep to the floor the light sees, the start is found and the check fails or passes.
  const FrameResult none = render(scene_from_yaml(kFlatMirror), "caustic_mapping", {"search_iterations=0"});
  const nlohmann::json& flat = none.method_record["passes"][0];
  std::printf("flat mirror at 0 iterations: %s of %s searches failed, %s at their start\n", flat["search_failed"].dump().c_str(),
              flat["photons"].dump().c_str(), flat["search_failed_at_start"].dump().c_str());
  EXPECT_EQ(flat["search_failed_at_start"], 0);
  EXPECT_NE(none.lost_flux->knob, "intersection");
}
