// What a scene requires (issue 52): the reference's split of its caustic flux into light-path classes
// (core/path_classes.h, methods/reference/path_class_tally.h) against scenes whose answer is known in
// closed form. Fixed seeds; each tolerance states its reason.
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/optics.h"
#include "core/photon_tracer.h"
#include "core/tracer.h"
#include "core/path_classes.h"
#include "core/image_statistics.h"
#include "core/scene.h"
#include "tests/test_support.h"

using namespace causticbench;
using causticbench::testing::render;
using causticbench::testing::scene_from_yaml;

namespace {

// Four stratified passes: the shares' standard errors come from their spread.
FrameResult reference_of(const Scene& scene, int frame = 0) {
  return render(scene, "reference",
                {"photons_per_pass=100000", "max_passes=4", "min_passes=4", "target_error=0", "max_seconds=0"}, frame);
}

const nlohmann::json& entry(const FrameResult& result, const std::string& where, const std::string& group,
                            const std::string& name) {
  return result.method_record.at("path_classes").at(where).at(group).at(name);
}

double share(const FrameResult& result, const std::string& where, const std::string& group, const std::string& name) {
  return entry(result, where, group, name).at("share").get<double>();
}

Scene capability_case(const std::string& name) {
  return load_scene(causticbench::testing::shipped_scenes() + "/capabilities/" + name + ".yaml");
}

// A glass slab (n = 1.5, 1 x 0.2 x 1, its top at 0.7) over a floor, under light from straight above.
const std::string kGlassSlab = R"(
camera: {type: orthographic, position: [0, 5, 0.01], look_at: [0, 0, 0], view_height: 4, resolution: [24, 24]}
lights: [{type: directional, direction: [0, -1, 0], irradiance: 1}]
objects:
  - shape: {type: quad, size: [8, 8]}
    material: {type: diffuse}
  - shape: {type: box, size: [1, 0.2, 1]}
    material: {type: glass, ior: 1.5}
    transform: {translate: [0, 0.6, 0]}
)";

}  // namespace

TEST(PathClassifier, ClassesEverySequenceOfEvents) {
  auto after = [](auto&& events) {
    PathClassifier path;
    events(path);
    return path.interaction();
  };
  EXPECT_EQ(after([](PathClassifier& p) { p.reflection(1, false); }), PathInteraction::one_reflection);
  EXPECT_EQ(after([](PathClassifier& p) { p.reflection(1, false), p.reflection(2, false); }), PathInteraction::multiple);
  EXPECT_EQ(after([](PathClassifier& p) { p.refraction(1, true); }), PathInteraction::one_pass);  // water
  EXPECT_EQ(after([](PathClassifier& p) { p.refraction(1, true), p.refraction(1, false); }), PathInteraction::one_pass);
  // An internal reflection, a second object, the same object entered again (a torus's arm to arm), a
  // reflection after the pass, and a refraction after a reflection are all multiple.
  EXPECT_EQ(after([](PathClassifier& p) { p.refraction(1, true), p.reflection(1, true), p.refraction(1, false); }),
            PathInteraction::multiple);
  EXPECT_EQ(after([](PathClassifier& p) { p.refraction(1, true), p.refraction(1, false), p.refraction(2, true); }),
            PathInteraction::multiple);
  EXPECT_EQ(after([](PathClassifier& p) {
              p.refraction(1, true), p.refraction(1, false), p.refraction(1, true), p.refraction(1, false);
            }),
            PathInteraction::multiple);
  EXPECT_EQ(after([](PathClassifier& p) { p.refraction(1, true), p.refraction(1, false), p.reflection(3, false); }),
            PathInteraction::multiple);
  EXPECT_EQ(after([](PathClassifier& p) { p.reflection(3, false), p.refraction(1, true); }), PathInteraction::multiple);
  // A reflection off a mirror under water (inside a medium) after entering it: multiple.
  EXPECT_EQ(after([](PathClassifier& p) { p.refraction(1, true), p.reflection(3, true); }), PathInteraction::multiple);
  // Every class packs into its byte and back (interaction, light, receiver, blocked).
  for (unsigned byte = 0; byte < 64; ++byte) {
    const PathClass path = PathClass::unpack(static_cast<uint8_t>(byte));
    if (static_cast<int>(path.interaction) < kPathInteractions && static_cast<int>(path.light) < kPathLights) {
      EXPECT_EQ(path.packed(), byte);
    }
  }
  const PathClass blocked{PathInteraction::multiple, PathLight::point, PathReceiver::non_lambertian, true};
  EXPECT_EQ(PathClass::unpack(blocked.packed()).receiver, PathReceiver::non_lambertian);
  EXPECT_TRUE(PathClass::unpack(blocked.packed()).blocked);
}

// One mirror, one reflection: every photon of the capability case's twin (the second periscope mirror
// alone, lit from the side) is one reflection; the periscope's own floor sees light only after both
// mirrors, so all of it is multiple. Exact: no other path reaches a receiver.
TEST(ReferencePathClasses, OneMirrorIsOneReflectionAndAPeriscopeIsMultiple) {
  const FrameResult one = reference_of(capability_case("multiple_bounces_without"));
  ASSERT_GT(one.method_record.at("path_classes").at("in_view").at("pixel_sum").get<double>(), 0.0);
  EXPECT_DOUBLE_EQ(share(one, "in_view", "interaction", "one_reflection"), 1.0);
  EXPECT_DOUBLE_EQ(share(one, "everywhere", "interaction", "one_reflection"), 1.0);
  EXPECT_DOUBLE_EQ(share(one, "in_view", "light", "directional"), 1.0);
  EXPECT_EQ(entry(one, "in_view", "interaction", "one_reflection").at("capability"), "reflection");
  const FrameResult periscope = reference_of(capability_case("multiple_bounces"));
  ASSERT_GT(periscope.method_record.at("path_classes").at("in_view").at("pixel_sum").get<double>(), 0.0);
  EXPECT_DOUBLE_EQ(share(periscope, "in_view", "interaction", "multiple"), 1.0);
  EXPECT_EQ(entry(periscope, "in_view", "interaction", "multiple").at("capability"), "multiple_bounces");
}

// Wavy water over a pool floor, the camera under the surface: the light enters the water once and lands
// on the floor inside it, so all of it is one pass (refraction). The waves are gentle, so that no
// refracted ray meets the surface again from below.
TEST(ReferencePathClasses, WaterIsOnePass) {
  const FrameResult water = reference_of(capability_case("refraction"), 1);
  ASSERT_GT(water.method_record.at("path_classes").at("in_view").at("pixel_sum").get<double>(), 0.0);
  EXPECT_DOUBLE_EQ(share(water, "in_view", "interaction", "one_pass"), 1.0);
  EXPECT_EQ(entry(water, "in_view", "interaction", "one_pass").at("capability"), "refraction");
}

// A glass slab (n = 1.5, 0.2 thick) 0.5 above the floor under light from straight above: the light goes
// in and out with weight (1 - F)^2 (one pass), or is reflected inside 2k times first, (1 - F)^2 F^(2k)
// (multiple); the light reflected off the top leaves upwards. The floor receives (1 - F)^2 / (1 - F^2)
// in all, of which (1 - F)^2 F^2 / (1 - F^2) is multiple: a share of exactly F^2, with
// F = ((n - 1) / (n + 1))^2 = 0.04: 0.0016. Bounded at four standard errors of the reference's own
// estimate (about 600 of the 400,000 photons).
TEST(ReferencePathClasses, AGlassSlabsInternalReflectionsAreItsMultipleShare) {
  const Scene slab = scene_from_yaml(kGlassSlab);
  const FrameResult result = reference_of(slab);
  const double fresnel = fresnel_dielectric(1.0f, 1.5f);
  ASSERT_NEAR(fresnel, 0.04, 1e-6);
  const nlohmann::json& multiple = entry(result, "everywhere", "interaction", "multiple");
  const double error = multiple.at("standard_error").get<double>();
  std::printf("slab: multiple share %.5f (standard error %.5f), closed form %.5f\n", multiple.at("share").get<double>(),
              error, fresnel * fresnel);
  EXPECT_GT(error, 0.0);
  EXPECT_NEAR(multiple.at("share").get<double>(), fresnel * fresnel, 4.0 * error + 1e-5);
  EXPECT_NEAR(share(result, "everywhere", "interaction", "one_pass"), 1.0 - fresnel * fresnel, 4.0 * error + 1e-5);
  EXPECT_DOUBLE_EQ(share(result, "everywhere", "interaction", "one_reflection"), 0.0);
}

// Each light kind is its own class: the point-light case's light is all point light, the environment
// case's all environment.
TEST(ReferencePathClasses, EachLightKindIsItsOwnClass) {
  const FrameResult point = reference_of(capability_case("point_light"), 1);
  EXPECT_DOUBLE_EQ(share(point, "in_view", "light", "point"), 1.0);
  EXPECT_EQ(entry(point, "in_view", "light", "point").at("capability"), "point_light");
  const FrameResult environment = reference_of(capability_case("environment_light"), 1);
  EXPECT_DOUBLE_EQ(share(environment, "in_view", "light", "environment"), 1.0);
  EXPECT_DOUBLE_EQ(share(environment, "in_view", "interaction", "one_reflection"), 1.0);
}

// Two independent measures of the same split on the glass sphere: the classes the tracer tags, and the
// reference's images cut at max_bounces 1 (only one reflection reaches a receiver) and 2 (also in and
// out; any other path off a lone convex ball needs three events). So one_reflection is S(1) / S and
// one_pass is (S(2) - S(1)) / S, S the image's E_c summed over the receiver pixels as an energy ratio
// sums it (the mean of the channels): the same photons (one seed) in all three, so they agree exactly (0.0402 and
// 0.9572 of the image's light) unless the tags and the cut disagree on some path or the split weights
// the light otherwise than the image does; bounded at 1e-4. The split's in-view total is the image's sum
// itself (to rounding, 1e-6). Broken on purpose (the in-view light weighted by flux alone, as before
// issue 52's review: the perspective camera sees the far reflections at fewer pixels per area):
// one_reflection 0.0336 against 0.0402, and the in-view total off the image's sum: fails.
TEST(ReferencePathClasses, TheSplitAgreesWithTheReferenceCutAtOneAndTwoBounces) {
  const Scene sphere = load_scene(causticbench::testing::shipped_scenes() + "/glass_sphere.yaml");
  const std::vector<std::string> knobs = {"photons_per_pass=200000", "max_passes=4", "min_passes=4", "target_error=0",
                                          "max_seconds=0"};
  auto image_sum = [](const FrameResult& result) { return masked_sum(result.caustic, result.gbuffer.receiver); };
  auto sum_with_bounces = [&](int bounces) {
    std::vector<std::string> cut = knobs;
    cut.push_back("max_bounces=" + std::to_string(bounces));
    return image_sum(render(sphere, "reference", cut));
  };
  const FrameResult full = render(sphere, "reference", knobs);
  const double total = image_sum(full);
  ASSERT_GT(total, 0.0);
  EXPECT_NEAR(full.method_record.at("path_classes").at("in_view").at("pixel_sum").get<double>() / total, 1.0, 1e-6);
  const double one = sum_with_bounces(1), two = sum_with_bounces(2);
  std::printf("glass sphere in view: one_reflection %.4f (cut at 1: %.4f), one_pass %.4f (cut at 2 less 1: %.4f)\n",
              share(full, "in_view", "interaction", "one_reflection"), one / total,
              share(full, "in_view", "interaction", "one_pass"), (two - one) / total);
  EXPECT_NEAR(share(full, "in_view", "interaction", "one_reflection"), one / total, 1e-4);
  EXPECT_NEAR(share(full, "in_view", "interaction", "one_pass"), (two - one) / total, 1e-4);
}

// Coloured light is weighted as an energy ratio sums an image, by the mean of its channels: the glass
// ball of the absorbing extreme keeps e^-5, e^-10 and e^-20 of the red, green and blue light it lets
// through, so its one pass is red while its reflection stays white. The reflection's share is the
// reference image cut at one bounce over the whole image, summed by masked_sum (measured 0.9091 both);
// broken on purpose (the in-view light weighted by luminance): 0.9383, fails.
TEST(ReferencePathClasses, ColouredLightIsWeightedAsTheEnergyRatioSumsIt) {
  Scene ball = load_scene(causticbench::testing::shipped_scenes() + "/extremes/absorbing.yaml");
  set_resolution(ball, 64, 64);
  const std::vector<std::string> knobs = {"photons_per_pass=200000", "max_passes=2", "min_passes=2", "target_error=0",
                                          "max_seconds=0"};
  std::vector<std::string> cut = knobs;
  cut.push_back("max_bounces=1");
  const FrameResult full = render(ball, "reference", knobs);
  const FrameResult reflected = render(ball, "reference", cut);
  const double total = masked_sum(full.caustic, full.gbuffer.receiver);
  ASSERT_GT(total, 0.0);
  const double expected = masked_sum(reflected.caustic, reflected.gbuffer.receiver) / total;
  std::printf("absorbing ball in view: one_reflection %.4f (cut at 1: %.4f)\n",
              share(full, "in_view", "interaction", "one_reflection"), expected);
  EXPECT_NEAR(share(full, "in_view", "interaction", "one_reflection"), expected, 1e-4);
  EXPECT_NEAR(full.method_record.at("path_classes").at("in_view").at("pixel_sum").get<double>() / total, 1.0, 1e-6);
}

// An occluder across the beam (issue 52): a glass slab (1 x 0.2 x 1, its top at 0.7) over a floor under
// light from straight above, which no path turns from the vertical. A diffuse plate above the slab over
// x in [0, 0.6] blocks exactly the half of the light bound for the slab that it covers. The slab sends
// T = (1 - F) / (1 + F) of its light down to the floor (in and out, with every pair of internal
// reflections) and R = 1 - T back up, F = 0.04 at normal incidence. Where it is not covered, T arrives
// (R leaves upwards); where it is, T would have arrived on the floor and R on the plate's underside. So
// the blocked light is T + R = 1 against T arrived: occlusion share 1 / (1 + T) = (1 + F) / 2 = 0.52 and
// excess (blocked over arrived) 1 / T = (1 + F) / (1 - F) = 1.0833. The same plate between the slab and
// the floor blocks nothing on the way to the slab: it receives the light through the half it covers, and
// the floor behind it would have, so the blocked light is half of what arrives (excess 0.5, share 1/3).
// Everywhere, where the closed form holds for every photon; the shares bounded at four of the reference's
// standard errors, the excess (a ratio of the same sums) at 0.005.
TEST(ReferencePathClasses, AnOccluderAcrossTheBeamBlocksTheShareOfTheBeamItCovers) {
  auto slab_with_plate_at = [](double height) {
    return scene_from_yaml(kGlassSlab + R"(  - shape: {type: quad, size: [0.6, 1.4]}
    material: {type: diffuse}
    transform: {translate: [0.3, )" + std::to_string(height) + R"(, 0]}
)");
  };
  const FrameResult above = reference_of(slab_with_plate_at(1.0));
  const nlohmann::json& before = above.method_record.at("path_classes").at("everywhere").at("occlusion");
  std::printf("plate above the slab: occlusion share %.4f (standard error %.4f), excess %.4f\n",
              before.at("share").get<double>(), before.at("standard_error").get<double>(),
              before.at("excess").get<double>());
  EXPECT_EQ(before.at("capability"), "occlusion");
  const double fresnel = fresnel_dielectric(1.0f, 1.5f);
  EXPECT_NEAR(before.at("share").get<double>(), (1.0 + fresnel) / 2.0,
              4.0 * before.at("standard_error").get<double>() + 1e-4);
  EXPECT_NEAR(before.at("excess").get<double>(), (1.0 + fresnel) / (1.0 - fresnel), 0.005);
  const FrameResult below = reference_of(slab_with_plate_at(0.3));
  const nlohmann::json& behind = below.method_record.at("path_classes").at("everywhere").at("occlusion");
  std::printf("plate under the slab: occlusion share %.4f (standard error %.4f), excess %.4f\n",
              behind.at("share").get<double>(), behind.at("standard_error").get<double>(),
              behind.at("excess").get<double>());
  EXPECT_NEAR(behind.at("share").get<double>(), 1.0 / 3.0, 4.0 * behind.at("standard_error").get<double>() + 1e-4);
  EXPECT_NEAR(behind.at("excess").get<double>(), 0.5, 0.005);
  // Without the plate nothing is blocked, and the photons that arrive are the same with the split or without.
  const FrameResult open = reference_of(scene_from_yaml(kGlassSlab));
  EXPECT_DOUBLE_EQ(open.method_record.at("path_classes").at("everywhere").at("occlusion").at("share").get<double>(), 0.0);
}

// Following blocked paths changes nothing of the light that arrives: the same photons, bit for bit, with
// the same classes and counts (but the rays traced), whether the tracer follows them or not, on scenes with
// both kinds of blocked path (a plate above and under a slab, a wall beside a ball's caustic), under
// stratified emission as the reference traces.
TEST(ReferencePathClasses, FollowingBlockedPathsLeavesTheArrivingPhotonsBitIdentical) {
  const std::vector<Scene> scenes = {
      scene_from_yaml(kGlassSlab + "  - shape: {type: quad, size: [0.6, 1.4]}\n    material: {type: diffuse}\n"
                                   "    transform: {translate: [0.3, 1.0, 0]}\n"),
      scene_from_yaml(kGlassSlab + "  - shape: {type: quad, size: [0.6, 1.4]}\n    material: {type: diffuse}\n"
                                   "    transform: {translate: [0.3, 0.3, 0]}\n"),
      load_scene(causticbench::testing::shipped_scenes() + "/glass_sphere_wall.yaml")};
  for (const Scene& scene : scenes) {
    SceneFrame frame(scene, 0);
    Tracer tracer(frame);
    PhotonTracerSettings settings{11};
    settings.stratified_pass_size = 50000;
    const CausticPhotonTracer photon_tracer(tracer, settings);
    std::vector<Photon> plain, followed;
    std::vector<uint8_t> plain_classes, followed_classes;
    PhotonStats plain_stats, followed_stats;
    CausticPhotonTracer::Blocked blocked;
    photon_tracer.trace(0, 100000, plain, plain_stats, plain_classes);
    photon_tracer.trace(0, 100000, followed, followed_stats, followed_classes, &blocked);
    ASSERT_GT(plain.size(), 1000u);
    EXPECT_GT(blocked.photons.size(), 100u) << "the scene has blocked paths to follow";
    EXPECT_EQ(blocked.photons.size(), blocked.classes.size());
    ASSERT_EQ(plain.size(), followed.size());
    EXPECT_EQ(0, std::memcmp(plain.data(), followed.data(), plain.size() * sizeof(Photon)));
    EXPECT_EQ(plain_classes, followed_classes);
    EXPECT_EQ(plain_stats.emitted, followed_stats.emitted);
    EXPECT_EQ(plain_stats.deposited, followed_stats.deposited);
    EXPECT_EQ(plain_stats.cut, followed_stats.cut);
    EXPECT_GT(followed_stats.rays, plain_stats.rays);
    for (uint8_t byte : blocked.classes) EXPECT_TRUE(PathClass::unpack(byte).blocked);
  }
}

// A glossy floor is a non-Lambertian receiver: all the light of the receiver case lands on one, none of
// its twin's (a diffuse floor).
TEST(ReferencePathClasses, AGlossyFloorIsANonLambertianReceiver) {
  const FrameResult glossy = reference_of(capability_case("non_lambertian_receivers"), 1);
  ASSERT_GT(glossy.method_record.at("path_classes").at("in_view").at("pixel_sum").get<double>(), 0.0);
  EXPECT_DOUBLE_EQ(share(glossy, "in_view", "receiver", "non_lambertian"), 1.0);
  EXPECT_EQ(entry(glossy, "in_view", "receiver", "non_lambertian").at("capability"), "non_lambertian_receivers");
  const FrameResult diffuse = reference_of(capability_case("non_lambertian_receivers_without"), 1);
  EXPECT_DOUBLE_EQ(share(diffuse, "in_view", "receiver", "lambertian"), 1.0);
}

// Issue 52, item 4: the capability matrix's cases and the split agree on what each case requires. On each
// case of a capability the split classifies (a light kind or a kind of specular interaction), the share of
// the reference's light in view that needs the capability (the joint classes naming it) is most of the
// light: a method that declares the capability false gets a model share of at least that much there,
// which is what its "no" in the matrix says. Measured (frame 1, 4 x 100,000 photons): 1.0000 on all seven
// cases (each case is built on one mirror or glass object under one light, and the receiver case on one
// glossy floor; bounded at 0.95). The occlusion case's wall blocks light rather than carrying it: what a
// method without occlusion may add there (the split's occlusion excess in view) is beyond the light
// account's tolerance (experiments/light_account.h), so that its "no" shows, and nothing is blocked in its
// twin. The motion cases have no class in the split (a moving light takes the same paths).
TEST(ReferencePathClasses, EachCapabilityCaseIsMostlyLightThatNeedsItsCapability) {
  const double tolerance = 0.15;  // kUnexplainedLightTolerance (experiments/, not linked here)
  for (const std::string capability : {"reflection", "refraction", "multiple_bounces", "directional_light",
                                       "point_light", "environment_light", "non_lambertian_receivers"}) {
    const FrameResult result = reference_of(capability_case(capability), 1);
    double needing = 0.0;
    for (const auto& [pair, joint] : result.method_record.at("path_classes").at("in_view").at("joint").items())
      for (const nlohmann::json& named : joint.at("capabilities"))
        if (named == capability) needing += joint.at("share").get<double>();
    std::printf("%s case: %.4f of the light in view needs it\n", capability.c_str(), needing);
    EXPECT_GT(needing, 0.95) << capability;
  }
  const FrameResult occluded = reference_of(capability_case("occlusion"), 1);
  const double excess = occluded.method_record.at("path_classes").at("in_view").at("occlusion").at("excess").get<double>();
  std::printf("occlusion case: occluders block %.4f of the light that arrives in view (excess)\n", excess);
  EXPECT_GT(excess, tolerance);
  const FrameResult open = reference_of(capability_case("occlusion_without"), 1);
  EXPECT_DOUBLE_EQ(open.method_record.at("path_classes").at("in_view").at("occlusion").at("excess").get<double>(), 0.0);
}
