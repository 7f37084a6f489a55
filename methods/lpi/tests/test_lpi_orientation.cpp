// lpi's orientation (issue 52): the paper's cosine (Section 3.2) measured by probe photons
// (methods/common/caustic_reach.h, paper_orientation_share), counted as lost flux, and `orientation: auto`
// (methods/lpi/orientation_choice.h), which takes the paper's orientation only where that cosine keeps
// the light.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "core/image_statistics.h"
#include "core/scene.h"
#include "tests/test_support.h"

using namespace causticbench;
using causticbench::testing::render;
using causticbench::testing::scene_from_yaml;

namespace {

double flux_in_view(const FrameResult& result) { return masked_sum(result.caustic, result.gbuffer.receiver); }

Scene small_ring() {
  Scene scene = load_scene(std::string(CAUSTICBENCH_SCENES) + "/ring.yaml");
  set_resolution(scene, 64, 64);
  return scene;
}

// A small flat mirror under a sun 45 degrees high sends its beam along the mirror's own radial
// directions onto a receiver facing back at it: the paper's cosine keeps all but the beam's spread
// (cos^2 of at most 0.1 rad).
const char* const kMirrorToWall = R"(
camera: {type: orthographic, position: [0.2, 0.2, 0], look_at: [0.7, 0.7, 0], up: [0, 0, 1], view_height: 0.6, resolution: [16, 16]}
lights: [{type: directional, direction: [0.7071068, -0.7071068, 0], irradiance: 1}]
objects:
  - name: wall
    shape: {type: quad, size: [0.6, 0.6]}
    material: {type: diffuse, albedo: 0.8}
    transform: {translate: [0.7, 0.7, 0], rotate: [0, 0, 135]}
  - name: mirror
    shape: {type: quad, size: [0.2, 0.2]}
    material: {type: mirror, reflectance: 1}
)";

}  // namespace

// Two independent measures of the paper orientation's loss on the ring, whose light falls on the table
// inside it, a surface facing away from the ring's centre: the probes' count (one photon at a time,
// through the share's formula) and the rendered images (the volumes' deposits and lookups, paper
// against vector from the same photons). Measured: the probes keep 0.169, the images 0.171. Following
// the advice, orientation: vector, takes the lost flux to nothing. Broken on purpose (the share without
// its 1 / |n . d|): the probes keep 0.084, fails.
TEST(LpiOrientation, ThePaperCosinesLossOnTheRingIsWhatItsImageLacks) {
  const Scene scene = small_ring();
  const std::vector<std::string> common = {"grid_resolution=48", "photons_per_sample=100000"};
  std::vector<std::string> paper = common, vector = common;
  paper.push_back("orientation=paper");
  vector.push_back("orientation=vector");
  const FrameResult paper_run = render(scene, "lpi", paper);
  const FrameResult vector_run = render(scene, "lpi", vector);
  ASSERT_TRUE(paper_run.lost_flux && vector_run.lost_flux);
  const double kept = flux_in_view(paper_run) / flux_in_view(vector_run);
  EXPECT_NEAR(1.0 - paper_run.lost_flux->fraction, kept, 0.03);
  EXPECT_GT(paper_run.lost_flux->fraction, 0.7);
  EXPECT_EQ(paper_run.lost_flux->knob, "orientation");
  EXPECT_NE(paper_run.lost_flux->advice.find("orientation: vector"), std::string::npos);
  EXPECT_LT(vector_run.lost_flux->fraction, 0.02) << "following the advice";
}

// auto follows the scene: on the ring the vector irradiance (the same image as orientation: vector),
// for the mirror's beam onto a facing wall the paper's (the same image as orientation: paper, and its
// cosine loses under the tolerance), and with one cell, which has no direction from the centre, vector
// where orientation: paper is refused.
TEST(LpiOrientation, AutoTakesThePapersOrientationOnlyWhereItsCosineKeepsTheLight) {
  const Scene ring = small_ring();
  const std::vector<std::string> ring_knobs = {"grid_resolution=16", "photons_per_sample=20000"};
  const FrameResult automatic = render(ring, "lpi", ring_knobs);
  std::vector<std::string> vector = ring_knobs;
  vector.push_back("orientation=vector");
  EXPECT_EQ(automatic.method_record["orientation"], "vector") << automatic.method_record["orientation_why"];
  EXPECT_EQ(automatic.caustic.values(), render(ring, "lpi", vector).caustic.values());

  const Scene mirror = scene_from_yaml(kMirrorToWall);
  const std::vector<std::string> mirror_knobs = {"grid_resolution=32", "photons_per_sample=20000", "volume_radius=8"};
  const FrameResult chosen = render(mirror, "lpi", mirror_knobs);
  EXPECT_EQ(chosen.method_record["orientation"], "paper") << chosen.method_record["orientation_why"];
  std::vector<std::string> paper = mirror_knobs;
  paper.push_back("orientation=paper");
  const FrameResult paper_run = render(mirror, "lpi", paper);
  EXPECT_GT(flux_in_view(paper_run), 0.0);
  EXPECT_EQ(chosen.caustic.values(), paper_run.caustic.values());
  ASSERT_TRUE(paper_run.lost_flux);
  EXPECT_LT(paper_run.lost_flux->fraction, 0.03);

  const FrameResult one_cell = render(mirror, "lpi", {"grid_resolution=1", "photons_per_sample=2000"});
  EXPECT_EQ(one_cell.method_record["orientation"], "vector");
  EXPECT_NE(one_cell.method_record["orientation_why"].get<std::string>().find("one cell"), std::string::npos);
}
