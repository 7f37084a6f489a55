// caustic_volume (Ernst et al. 2005): straight prisms on a flat mirror give the reflected beam exactly;
// the containment test against the forward map X(b, t) on random volumes (nearly parallel rays, folds);
// the cubic's roots; the interpolated intensity's continuity across a shared edge; energy on the ring;
// convergence to the reference as the tessellation is refined.
#include <cmath>
#include <cstdio>
#include <map>
#include <tuple>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "core/files.h"
#include "core/image_statistics.h"
#include "core/scene.h"
#include "core/tracer.h"
#include "metrics/flip.h"
#include "methods/common/analytic_mesh.h"
#include "methods/caustic_volume/volume.h"
#include "methods/caustic_volume/tests/scenes.h"
#include "tests/test_support.h"

using namespace causticbench;
using causticbench::testing::kBeamHalfX;
using causticbench::testing::kBeamHalfZ;
using causticbench::testing::kFlatMirror;
using causticbench::testing::kRingFromAbove;
using causticbench::testing::render;
using causticbench::testing::scene_from_yaml;
namespace cv = causticbench::caustic_volume;

namespace {


double pixel_area(const Scene& scene) {
  const double side = scene.camera.view_height / scene.camera.height;
  return side * side;
}

}  // namespace

// Every volume of a flat mirror is a straight prism: inside the reflected beam E_c is the reflected
// irradiance, 1.8, to rounding, with either intensity, and nothing outside, so the pixels' sum is exactly
// 1.8 times the area of the pixels whose points lie in the beam (the point-sampled beam: 2 % under the
// beam's flux at 96^2, its width being 18.4 pixels); nothing is lost.
TEST(CausticVolume, FlatMirrorGivesTheReflectedBeamExactly) {
  const Scene scene = scene_from_yaml(kFlatMirror);
  for (const char* intensity : {"intensity=interpolated", "intensity=constant"}) {
    const FrameResult result = render(scene, "caustic_volume", {intensity});
    ASSERT_TRUE(result.lost_flux);
    EXPECT_EQ(result.lost_flux->fraction, 0.0) << intensity;
    double flux = 0.0, largest_error = 0.0, outside = 0.0, sampled_beam = 0.0;
    int interior = 0;
    for (size_t pixel = 0; pixel < result.gbuffer.pixel_count(); ++pixel) {
      if (!result.gbuffer.receiver[pixel]) continue;
      const double value = result.caustic.at(pixel, 1);
      flux += value * pixel_area(scene);
      const Vec3& p = result.gbuffer.position[pixel];
      const double dx = std::abs(p.x - 1.5), dz = std::abs(p.z);
      if (dx < kBeamHalfX && dz < kBeamHalfZ) sampled_beam += 1.8 * pixel_area(scene);
      if (dx < kBeamHalfX - 0.02 && dz < kBeamHalfZ - 0.02) {
        largest_error = std::max(largest_error, std::abs(value - 1.8));
        ++interior;
      } else if (dx > kBeamHalfX + 0.02 || dz > kBeamHalfZ + 0.02) {
        outside = std::max(outside, value);
      }
    }
    const double beam = 1.8 * (2 * kBeamHalfX) * (2 * kBeamHalfZ);
    std::printf("%s: interior pixels %d, largest |E - 1.8| %.3g, flux %.6f against the sampled beam's %.6f (the beam's %.5f)\n",
                intensity, interior, largest_error, flux, sampled_beam, beam);
    EXPECT_GT(interior, 200);
    EXPECT_LT(largest_error, 1e-4) << intensity;
    EXPECT_EQ(outside, 0.0) << intensity;
    EXPECT_NEAR(flux, sampled_beam, 1e-5 * beam) << intensity;
    EXPECT_NEAR(flux, beam, 0.025 * beam) << intensity;
  }
}

// The cubic's roots, where it is a cubic, nearly quadratic, linear, and where roots lie outside [0, t_max].
TEST(CausticVolume, CubicRootsAreFoundWhereverTheCubicDegenerates) {
  double roots[3];
  // (t - 1)(t - 2)(t - 3)
  ASSERT_EQ(cv::cubic_roots(-6, 11, -6, 1, 4.0, roots), 3);
  EXPECT_NEAR(roots[0], 1.0, 1e-10);
  EXPECT_NEAR(roots[1], 2.0, 1e-10);
  EXPECT_NEAR(roots[2], 3.0, 1e-10);
  ASSERT_EQ(cv::cubic_roots(-6, 11, -6, 1, 2.5, roots), 2);  // 3 beyond the cap
  // Nearly quadratic: 1e-15 t^3 + (t - 0.5)(t - 1.5).
  ASSERT_EQ(cv::cubic_roots(0.75, -2.0, 1.0, 1e-15, 2.0, roots), 2);
  EXPECT_NEAR(roots[0], 0.5, 1e-9);
  EXPECT_NEAR(roots[1], 1.5, 1e-9);
  // Linear (a prism): 2 - 4 t.
  ASSERT_EQ(cv::cubic_roots(2.0, -4.0, 0.0, 0.0, 1.0, roots), 1);
  EXPECT_NEAR(roots[0], 0.5, 1e-12);
  // None in range.
  EXPECT_EQ(cv::cubic_roots(1.0, 1.0, 1.0, 1.0, 10.0, roots), 0);
}

namespace {

cv::Volume random_volume(std::mt19937& random, double spread, double t_max) {
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  cv::Volume volume;
  volume.t_max = t_max;
  const glm::dvec3 axis = glm::normalize(glm::dvec3(uniform(random), -1.5, uniform(random)));
  for (int i = 0; i < 3; ++i) {
    volume.origin[i] = glm::dvec3(uniform(random), 0.2 * uniform(random), uniform(random));
    volume.direction[i] = glm::normalize(axis + spread * glm::dvec3(uniform(random), uniform(random), uniform(random)));
  }
  cv::finish_volume(volume);
  return volume;
}

}  // namespace

// The containment test against the forward map: for random volumes (straight prisms, nearly parallel
// rays, strongly converging rays whose cross-sections fold over), every point X(b, t) made from a
// random b and t is found on a sheet with that t and those weights, and every sheet found for a random
// point maps back to it, X(w, t) = x. At most three sheets, as a cubic allows. Fixed seed.
TEST(CausticVolume, ContainmentAgreesWithTheForwardMapIncludingFoldsAndNearlyParallelRays) {
  std::mt19937 random(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int folds = 0;
  for (double spread : {0.0, 1e-9, 1e-4, 0.3, 1.5}) {
    for (int trial = 0; trial < 200; ++trial) {
      const cv::Volume volume = random_volume(random, spread, 4.0);
      // Forward: a point of the volume is found where it was made.
      double b1 = unit(random), b2 = unit(random);
      if (b1 + b2 > 1.0) b1 = 1.0 - b1, b2 = 1.0 - b2;
      const double b[3] = {1.0 - b1 - b2, b1, b2};
      const double t = 4.0 * unit(random);
      glm::dvec3 x(0.0);
      for (int i = 0; i < 3; ++i) x += b[i] * (volume.origin[i] + t * volume.direction[i]);
      cv::Sheet sheets[3];
      const int count = cv::sheets_through(volume, x, sheets);
      ASSERT_LE(count, 3);
      folds += count > 1;
      bool found = false;
      for (int s = 0; s < count; ++s)
        found = found || (std::abs(sheets[s].t - t) < 1e-6 * (1.0 + t) && std::abs(sheets[s].weights[1] - b1) < 1e-6 &&
                          std::abs(sheets[s].weights[2] - b2) < 1e-6);
      // A cross-section of no area (three rays meeting in one point, or on one line) holds nothing.
      const glm::dvec3 section = volume.k[0] + t * volume.k[1] + t * t * volume.k[2];
      if (glm::length(section) > 1e-6) {
        EXPECT_TRUE(found) << "spread " << spread << " trial " << trial << " t " << t;
      }
      // Backward: a random point's sheets each map back to it.
      const glm::dvec3 y = volume.lower + (volume.upper - volume.lower) * glm::dvec3(unit(random), unit(random), unit(random));
      const int back = cv::sheets_through(volume, y, sheets);
      for (int s = 0; s < back; ++s) {
        glm::dvec3 z(0.0);
        for (int i = 0; i < 3; ++i) z += sheets[s].weights[i] * (volume.origin[i] + sheets[s].t * volume.direction[i]);
        EXPECT_LT(glm::length(z - y), 1e-7) << "spread " << spread << " trial " << trial;
        EXPECT_GE(sheets[s].t, 0.0);
        EXPECT_LE(sheets[s].t, 4.0);
      }
    }
  }
  std::printf("points on more than one sheet: %d\n", folds);
  EXPECT_GT(folds, 0) << "the converging volumes should fold";
}

namespace {

// The volumes of the ring (kRingFromAbove) at `segments`, built as update() builds them.
struct RingVolumes {
  Scene scene = scene_from_yaml(kRingFromAbove);
  SceneFrame frame{scene, 0};
  Tracer tracer{frame};
  std::vector<cv::Volume> volumes;
  cv::BeamStatistics statistics;
  explicit RingVolumes(int segments) {
    const cv::ReceiverBox box = cv::receiver_box(frame);
    cv::build_volumes(tracer, frame.lights[0], surface_mesh(frame, 1, segments), 1, scene.objects[1].material,
                      cv::Refraction::automatic, 100.0,
                      &box, volumes, statistics);
  }
};

}  // namespace

// Neighbouring volumes share two vertex rays, and so the bilinear patch between them. With interpolated
// intensity each vertex carries one wavefront density, so on the patch both volumes give the same light
// (the third vertex's weight is 0): measured jump below 1e-6 of the value. The constant intensity's
// facets jump there (by more than 1 % at the median).
TEST(CausticVolume, InterpolatedIntensityIsContinuousAcrossSharedEdges) {
  const RingVolumes ring(64);
  std::map<std::pair<glm::dvec3, glm::dvec3>, size_t, bool (*)(const std::pair<glm::dvec3, glm::dvec3>&,
                                                                 const std::pair<glm::dvec3, glm::dvec3>&)>
      edges([](const auto& a, const auto& b) {
        auto key = [](const auto& e) { return std::make_tuple(e.first.x, e.first.y, e.first.z, e.second.x, e.second.y, e.second.z); };
        return key(a) < key(b);
      });
  std::mt19937 random(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<double> interpolated_jumps, constant_jumps;
  for (size_t v = 0; v < ring.volumes.size(); ++v) {
    const cv::Volume& volume = ring.volumes[v];
    for (int i = 0; i < 3; ++i) {
      const int j = (i + 1) % 3;
      auto edge = std::make_pair(volume.origin[i], volume.origin[j]);
      auto reversed = std::make_pair(volume.origin[j], volume.origin[i]);
      auto other = edges.find(reversed);
      if (other == edges.end()) {
        edges.emplace(edge, v);
        continue;
      }
      const cv::Volume& neighbour = ring.volumes[other->second];
      // The same two vertex rays from the same side (across the thin band's terminator a neighbour is lit from
      // the other side: another wavefront, whose rays a mirror reflects the same way).
      int at_i = -1, at_j = -1;
      for (int k = 0; k < 3; ++k) {
        if (neighbour.origin[k] == volume.origin[i]) at_i = k;
        if (neighbour.origin[k] == volume.origin[j]) at_j = k;
      }
      if (at_i < 0 || at_j < 0 || neighbour.side != volume.side || neighbour.direction[at_i] != volume.direction[i] ||
          neighbour.direction[at_j] != volume.direction[j])
        continue;
      // A point on the shared patch, on the way to the table.
      const double reach = std::min(volume.t_max, neighbour.t_max);
      const double s = 0.1 + 0.8 * unit(random), t = 0.2 * reach + 0.6 * reach * unit(random);
      const glm::dvec3 x = (1.0 - s) * (volume.origin[i] + t * volume.direction[i]) + s * (volume.origin[j] + t * volume.direction[j]);
      // Each volume's sheet through x at this t (a folding volume may have others elsewhere).
      cv::Sheet sheets_a[3], sheets_b[3];
      const int count_a = cv::sheets_through(volume, x, sheets_a), count_b = cv::sheets_through(neighbour, x, sheets_b);
      const cv::Sheet* on_a = nullptr;
      const cv::Sheet* on_b = nullptr;
      for (int k = 0; k < count_a; ++k) on_a = std::abs(sheets_a[k].t - t) < 1e-7 * (1.0 + t) ? &sheets_a[k] : on_a;
      for (int k = 0; k < count_b; ++k) on_b = std::abs(sheets_b[k].t - t) < 1e-7 * (1.0 + t) ? &sheets_b[k] : on_b;
      ASSERT_TRUE(on_a && on_b) << "a point of the shared patch lies on both volumes' boundary";
      const Color a = cv::beam_irradiance(volume, *on_a, cv::Intensity::interpolated);
      const Color b = cv::beam_irradiance(neighbour, *on_b, cv::Intensity::interpolated);
      const Color c = cv::beam_irradiance(volume, *on_a, cv::Intensity::constant);
      const Color d = cv::beam_irradiance(neighbour, *on_b, cv::Intensity::constant);
      if (a.g <= 0.0f || b.g <= 0.0f || c.g <= 0.0f || d.g <= 0.0f) continue;  // a shadowed vertex
      interpolated_jumps.push_back(std::abs(a.g - b.g) / std::max(a.g, b.g));
      constant_jumps.push_back(std::abs(c.g - d.g) / std::max(c.g, d.g));
    }
  }
  ASSERT_GT(interpolated_jumps.size(), 200u);
  std::sort(interpolated_jumps.begin(), interpolated_jumps.end());
  std::sort(constant_jumps.begin(), constant_jumps.end());
  std::printf("shared patch points %zu: interpolated jump largest %.3g; constant jump median %.3g, largest %.3g\n",
              interpolated_jumps.size(), interpolated_jumps.back(), constant_jumps[constant_jumps.size() / 2],
              constant_jumps.back());
  EXPECT_LT(interpolated_jumps.back(), 1e-5);
  EXPECT_GT(constant_jumps[constant_jumps.size() / 2], 0.01);
}

// Energy on a diverging beam: the ring's outer wall, convex, spreads its reflected light over the table
// without folds. The table's integral of each volume's E_c (a fine grid over the volume's bounds, 400
// points per unit length) is the flux entering the volumes: with constant intensity to 1 % at 32 and 64
// around (a prism's is exact; a warped volume's cross-section is measured across its mean direction);
// with interpolated intensity to 2 % at 64, converging (the error halves or better from 32 to 64: the
// interpolated tubes' areas are exact at the vertices only). Measured below. (Where a concave surface
// focuses, pixels sample a caustic's singular edges and their sum is only as good as the sampling: the
// ring's inner cardioid at 128^2 to 1024^2 pixels sums to 0.96 to 1.04 of its flux; that is the image's
// error, not the volumes'.)
TEST(CausticVolume, EnergyOfADivergingBeamIsTheVolumesFlux) {
  double interpolated_error_at_32 = 0.0;
  for (int segments : {32, 64}) {
    const RingVolumes ring(segments);
    for (cv::Intensity intensity : {cv::Intensity::interpolated, cv::Intensity::constant}) {
      double entering = 0.0, landed = 0.0;
      constexpr double kStep = 1.0 / 400.0;
      for (const cv::Volume& volume : ring.volumes) {
        const glm::dvec3 centroid = (volume.origin[0] + volume.origin[1] + volume.origin[2]) / 3.0;
        if (glm::dot(volume.mean_direction, glm::dvec3(centroid.x, 0.0, centroid.z)) <= 0.0) continue;  // inner wall
        entering += volume.flux;
        for (double x = std::floor(volume.lower.x / kStep) * kStep + 0.5 * kStep; x < volume.upper.x; x += kStep)
          for (double z = std::floor(volume.lower.z / kStep) * kStep + 0.5 * kStep; z < volume.upper.z; z += kStep)
            landed += luminance(cv::volume_irradiance(volume, glm::dvec3(x, 0.0, z), glm::dvec3(0, 1, 0), intensity)) *
                      kStep * kStep;
      }
      const char* name = intensity == cv::Intensity::interpolated ? "interpolated" : "constant";
      std::printf("tessellation %d %s: outer wall's volumes %.5f entering, %.5f on the table, ratio %.5f\n", segments, name,
                  entering, landed, landed / entering);
      if (intensity == cv::Intensity::constant) {
        EXPECT_NEAR(landed / entering, 1.0, 0.01) << segments << " " << name;
      } else if (segments == 64) {
        EXPECT_NEAR(landed / entering, 1.0, 0.02) << segments << " " << name;
        EXPECT_LT(std::abs(landed / entering - 1.0), 0.5 * interpolated_error_at_32) << "converging";
      } else {
        interpolated_error_at_32 = std::abs(landed / entering - 1.0);
      }
    }
  }
}

// The ring of Wand's Fig. 4 (ring.yaml's mirror and light, 96 x 96) against the reference: both
// intensities converge as the tessellation is refined (FLIP at 16, 64 and 256 around, each finer one
// better), and the interpolated intensity at the paper's 2 x 64 x 8 triangles is within the bound the
// measurement below states.
TEST(CausticVolume, RingConvergesToTheReferenceAsTheTessellationIsRefined) {
  std::string text = causticbench::testing::read_whole_file(std::string(CAUSTICBENCH_SCENES) + "/ring.yaml");
  text = causticbench::testing::replace_once(text, "resolution: [256, 256]", "resolution: [96, 96]");
  const Scene scene = scene_from_yaml(text);
  const FrameResult reference = render(scene, "reference", causticbench::testing::kSmallSceneReferenceKnobs);
  for (const char* intensity : {"intensity=interpolated", "intensity=constant"}) {
    double previous = 1.0;
    for (int segments : {16, 64, 256}) {
      const FrameResult result = render(scene, "caustic_volume", {intensity, "tessellation=" + std::to_string(segments)});
      const double flip = caustic_flip(result.caustic, reference.caustic, reference.gbuffer.receiver).mean;
      const double energy = masked_sum(result.caustic, result.gbuffer.receiver) / masked_sum(reference.caustic, reference.gbuffer.receiver);
      std::printf("%s tessellation %d: FLIP %.4f, energy %.4f\n", intensity, segments, flip, energy);
      EXPECT_LT(flip, previous) << intensity << " " << segments;
      previous = flip;
      if (segments == 64 && std::string(intensity) == "intensity=interpolated") {
        EXPECT_LT(flip, 0.09);
      }
    }
  }
}

namespace {

// A scene file of the capability study, at `resolution` squared.
Scene capability_scene(const std::string& name, int resolution) {
  std::string text = causticbench::testing::read_whole_file(std::string(CAUSTICBENCH_SCENES) + "/capabilities/" + name + ".yaml");
  text = causticbench::testing::replace_once(text, "resolution: [32, 32]",
                                             "resolution: [" + std::to_string(resolution) + ", " + std::to_string(resolution) + "]");
  return scene_from_yaml(text);
}

double relmse_against(const FrameResult& result, const FrameResult& reference) {
  return relative_mse(result.caustic, reference.caustic, reference.gbuffer.receiver);
}

}  // namespace

// A fixed max_distance short of the table: the flat mirror's beam goes straight down from mirror
// points (1.5 - 0.383 s, 1.5 + 0.924 s), s in [-0.3, 0.3] along the tilted quad, so a far cap at
// distance D leaves the floor unlit where 1.5 + 0.924 s > D: a share (0.3 - (D - 1.5) / 0.924) / 0.6
// of the beam's flux, in closed form. The method must report that share as lost (light meeting its
// first receiver beyond the far cap), and what it delivers plus what it reports lost is the beam.
TEST(CausticVolume, AFixedFarCapShortOfTheTableLosesTheBeamBeyondIt) {
  const Scene scene = scene_from_yaml(kFlatMirror);
  auto delivered = [&](const FrameResult& result) {
    double flux = 0.0;
    for (size_t pixel = 0; pixel < result.gbuffer.pixel_count(); ++pixel)
      if (result.gbuffer.receiver[pixel]) flux += result.caustic.at(pixel, 1) * pixel_area(scene);
    return flux;
  };
  const FrameResult whole = render(scene, "caustic_volume", {});
  ASSERT_TRUE(whole.lost_flux);
  EXPECT_EQ(whole.lost_flux->fraction, 0.0);
  const double beam = delivered(whole);
  const double half_width = 0.3, rise = std::sin(67.5 * kPiDouble / 180.0);  // the quad's vertical extent per unit s
  for (double cap : {1.4, 1.5, 1.6}) {
    const FrameResult result = render(scene, "caustic_volume", {"max_distance=" + std::to_string(cap)});
    ASSERT_TRUE(result.lost_flux);
    const double beyond = (half_width - (cap - 1.5) / rise) / (2.0 * half_width);
    const double share = delivered(result) / beam;
    std::printf("max_distance %.1f: lost %.4f (closed form %.4f), delivered %.4f of the whole beam\n", cap,
                result.lost_flux->fraction, beyond, share);
    EXPECT_NEAR(result.lost_flux->fraction, beyond, 0.01) << cap;
    EXPECT_NEAR(share + result.lost_flux->fraction, 1.0, 0.03) << cap;  // the pixels sample the beam's edge
    EXPECT_EQ(result.lost_flux->knob, "max_distance");
  }
}

// occlusion: shadow_rays. The capability case's wall stands in the mirror sphere's reflected fan: without
// shadow rays the volumes light the floor in the wall's shadow (relMSE above 10 at 48^2); with them the
// error drops below the capability bound (0.25) and the energy to within 15 % of the reference's.
// Measured below; one shadow ray a point and sheet.
TEST(CausticVolume, ShadowRaysKeepTheLightOutOfAnOccludersShadow) {
  const Scene scene = capability_scene("occlusion", 48);
  const FrameResult reference = render(scene, "reference", causticbench::testing::kSmallSceneReferenceKnobs);
  const FrameResult open = render(scene, "caustic_volume", {"tessellation=128"});
  const FrameResult shadowed = render(scene, "caustic_volume", {"tessellation=128", "occlusion=shadow_rays"});
  auto energy = [&](const FrameResult& result) {
    return masked_sum(result.caustic, reference.gbuffer.receiver) / masked_sum(reference.caustic, reference.gbuffer.receiver);
  };
  double rays = 0.0;
  for (const auto& [name, value] : shadowed.counters) rays = name == "shadow_rays" ? value : rays;
  std::printf("without shadow rays: relMSE %.3f, energy %.3f; with: relMSE %.4f, energy %.4f (%.0f rays)\n",
              relmse_against(open, reference), energy(open), relmse_against(shadowed, reference), energy(shadowed), rays);
  EXPECT_GT(relmse_against(open, reference), 10.0);
  EXPECT_LT(relmse_against(shadowed, reference), 0.25);
  EXPECT_NEAR(energy(shadowed), 1.0, 0.15);
  EXPECT_GT(rays, 0.0);
}

// refraction: through_object on the glass sphere (kSmallGlassSphere): each vertex ray followed through the
// ball to where it leaves, with the Fresnel transmittance of both interfaces. What it models is one path
// class of the reference's light: in through the ball and out again, two specular bounces. The reference
// itself isolates that class: max_bounces 1 keeps only the light reflected off the ball, max_bounces 2
// adds the straight pass (the same photons: one seed), so (max_bounces 2) - (max_bounces 1), per pixel,
// is the one-pass class (paths with internal reflections need three bounces or more). Measured in view:
// reflected 0.0336 of the reference, two bounces 0.9976, so the class is 0.964 (a Fresnel quadrature over
// the cross-section cannot give this: it does not say where each class lands in view). Against the
// class, caustic_volume's energy converges with tessellation as its silhouette does (quads around the
// axis: 0.961 of it at 64, 0.991 at 128, 0.9999 at 512; the sphere's rim, grazing, is where the
// polygon's flux differs most): at 512 it must hold the class within 1 % (the reference's sampling error
// of an in-view sum is a few tenths of a percent), and each doubling must close the gap. Per pixel it
// agrees with the class to relMSE 0.0027 at 64 and 0.0022 at 512 (the reference's own noise, about),
// bounded at 1.5 times that; against the whole reference it reads 0.075, the reflected light's. Refracting once,
// as if the floor lay inside the glass, is far off. auto picks through_object for the ball.
TEST(CausticVolume, ThroughTheGlassSphereAgainstTheReference) {
  const Scene scene = scene_from_yaml(causticbench::testing::kSmallGlassSphere);
  const FrameResult reference = render(scene, "reference", causticbench::testing::kSmallSceneReferenceKnobs);
  const std::vector<uint8_t>& receiver = reference.gbuffer.receiver;
  auto energy = [&](const Image& image) { return masked_sum(image, receiver) / masked_sum(reference.caustic, receiver); };
  std::vector<std::string> knobs = causticbench::testing::kSmallSceneReferenceKnobs;
  knobs.push_back("max_bounces=1");
  const FrameResult reflected = render(scene, "reference", knobs);
  knobs.back() = "max_bounces=2";
  const FrameResult two_bounces = render(scene, "reference", knobs);
  Image one_pass = two_bounces.caustic;
  for (size_t i = 0; i < one_pass.values().size(); ++i) one_pass.values()[i] -= reflected.caustic.values()[i];
  const double class_energy = energy(one_pass);
  std::printf("reference in view: reflected %.4f, two bounces %.4f: one pass through the ball %.4f\n",
              energy(reflected.caustic), energy(two_bounces.caustic), class_energy);
  EXPECT_GT(energy(reflected.caustic), 0.0);
  EXPECT_LT(energy(two_bounces.caustic), 1.0);

  double previous_gap = 1.0;
  for (int tessellation : {64, 128, 512}) {
    const FrameResult result =
        render(scene, "caustic_volume", {"refraction=through_object", "tessellation=" + std::to_string(tessellation)});
    const double gap = 1.0 - energy(result.caustic) / class_energy;
    const double relmse = relative_mse(result.caustic, one_pass, receiver);
    std::printf("tessellation %d: energy %.4f of the reference, %.4f of the class; relMSE to the class %.4f\n",
                tessellation, energy(result.caustic), 1.0 - gap, relmse);
    EXPECT_LT(std::abs(gap), previous_gap) << tessellation;
    previous_gap = std::abs(gap);
    if (tessellation == 512) {
      EXPECT_LT(std::abs(gap), 0.01);
      EXPECT_LT(relmse, 1.5 * 0.0022);
    }
    if (tessellation == 64) {  // the default
      EXPECT_LT(gap, 1.5 * 0.039);
      EXPECT_LT(relmse, 1.5 * 0.0027);
    }
  }
  const FrameResult through = render(scene, "caustic_volume", {"refraction=through_object"});
  const FrameResult automatic = render(scene, "caustic_volume", {});
  const FrameResult once = render(scene, "caustic_volume", {"refraction=one_interface"});
  std::printf("through_object: energy %.3f, relMSE %.3f, FLIP %.3f, torn %s, lost %.3f; one_interface: energy %.3f, FLIP %.3f\n",
              energy(through.caustic), relmse_against(through, reference), caustic_flip(through.caustic, reference.caustic, receiver).mean,
              through.method_record["volumes_torn"].dump().c_str(), through.lost_flux->fraction, energy(once.caustic),
              caustic_flip(once.caustic, reference.caustic, receiver).mean);
  EXPECT_EQ(through.lost_flux->fraction, 0.0);
  EXPECT_LT(caustic_flip(through.caustic, reference.caustic, receiver).mean,
            0.7 * caustic_flip(once.caustic, reference.caustic, receiver).mean);
  EXPECT_EQ(relative_mse(automatic.caustic, through.caustic, receiver), 0.0);
}

// Issue 52: the shipped glass cube (configs/scenes/glass_cube.yaml, at 64^2). Its faces were one beam per
// half face, 12 triangles at any tessellation: every lit beam's corner rays left through different faces
// (torn) or were trapped, so nothing reached the floor (lost flux 1.0) and the advice, "raise
// tessellation", changed nothing. The faces are now cut n x n (n = tessellation / 4, surface_mesh): the
// triangles tile the same faces (area 6 x 0.8^2 at every n), the beams reach the floor, and the torn share
// and the lost flux fall as the knob the advice names rises while the energy rises (measured here: lost
// 0.465, 0.193, 0.053 and energy 0.116, 0.471, 0.700 of the reference's at 16, 64, 256; volumes 59, 1281,
// 23472). The far cap's count no longer takes light landing on the floor at the cap for light beyond it
// (it read 0.294 at 256, with max_distance as its knob, while max_distance was auto already). What the
// lost flux does not explain at 256 (0.25) is the report's light account's to say.
TEST(CausticVolume, AGlassCubesFacesAreCutSoThatRaisingTessellationRecoversItsLight) {
  const std::string path = std::string(CAUSTICBENCH_SOURCE_DIR) + "/configs/scenes/glass_cube.yaml";
  const Scene scene = scene_from_yaml(causticbench::testing::replace_once(read_text(path), "resolution: [256, 256]",
                                                                           "resolution: [64, 64]"));
  const SceneFrame frame{scene, 0};
  const int cube = 1;
  for (int tessellation : {4, 16, 64}) {
    const SurfaceMesh mesh = surface_mesh(frame, cube, tessellation, true);
    double area = 0.0;
    for (const glm::uvec3& t : mesh.triangles)
      area += 0.5 * glm::length(glm::cross(mesh.positions[t.y] - mesh.positions[t.x], mesh.positions[t.z] - mesh.positions[t.x]));
    const size_t n = static_cast<size_t>(std::max(1, tessellation / 4));
    EXPECT_EQ(mesh.triangles.size(), 12 * n * n) << tessellation;
    EXPECT_NEAR(area, 6.0 * 0.8 * 0.8, 1e-6) << tessellation;  // the mesh is float
  }
  EXPECT_EQ(surface_mesh(frame, cube, 64).triangles.size(), 12u) << "without the cut: the scene's own triangles";

  const FrameResult reference = render(scene, "reference", causticbench::testing::kSmallSceneReferenceKnobs);
  const std::vector<uint8_t>& receiver = reference.gbuffer.receiver;
  double previous_lost = 1.0, previous_torn = 1.0, previous_energy = 0.0;
  for (int tessellation : {4, 16, 64, 256}) {
    const FrameResult result = render(scene, "caustic_volume", {"tessellation=" + std::to_string(tessellation)});
    ASSERT_TRUE(result.lost_flux);
    const double volumes = result.method_record["volumes"].get<double>();
    const double torn = result.method_record["volumes_torn"].get<double>() / std::max(1.0, volumes + result.method_record["volumes_torn"].get<double>());
    const double energy = masked_sum(result.caustic, receiver) / masked_sum(reference.caustic, receiver);
    std::printf("tessellation %d: %.0f volumes, torn share %.3f, lost %.3f, energy %.3f, energy + lost %.3f\n", tessellation,
                volumes, torn, result.lost_flux->fraction, energy, energy + result.lost_flux->fraction);
    if (tessellation == 4) {  // one beam a half face: what every tessellation gave before the cut
      EXPECT_EQ(volumes, 0.0);
      EXPECT_EQ(result.lost_flux->fraction, 1.0);
      continue;
    }
    EXPECT_GT(volumes, 0.0) << tessellation;
    EXPECT_LT(result.lost_flux->fraction, previous_lost) << tessellation;
    EXPECT_LT(torn, previous_torn) << tessellation;
    EXPECT_EQ(result.lost_flux->knob, "tessellation");
    previous_lost = result.lost_flux->fraction;
    previous_torn = torn;
    EXPECT_GT(energy, previous_energy) << tessellation;
    previous_energy = energy;
  }
}
