// csl's closed forms (Liu 2008, Section 2) and its fitting stages (Section 3.1) against independent
// computations: every radius the solver returns is confirmed by casting that spot light ray, Eq. 4
// equals the numerical derivative of the mapped area, the on-axis integration is the limit and the
// average of the off-axis values, a known spot light is fitted back from its own rays, and the DDA,
// the axis optimisation and the splat conserve what they should. The method against the reference:
// test_csl.cpp.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "methods/csl/bundles.h"
#include "methods/csl/csl.h"
#include "methods/csl/fit.h"
#include "methods/csl/splat.h"
#include "methods/csl/spot_light.h"
#include "tests/test_support.h"

using namespace causticbench;
using namespace causticbench::csl;

namespace {

// A spot light on the z axis from the origin with a constant image of `intensity` over a square of
// half size `half`.
SpotLight uniform_light(double kappa, double beta, float half = 2.0f, float intensity = 1.0f, int size = 128) {
  SpotLight light;
  light.origin = Vec3(0.0f);
  light.axis = Vec3(0.0f, 0.0f, 1.0f);
  set_plane_axes(light);
  light.profile = Profile{kappa, beta};
  light.image = IntensityImage(size, 1, half, std::vector<float>(static_cast<size_t>(size) * size, intensity),
                               IntensityImage::Precision::float32);
  return light;
}

const std::vector<Profile> kProfiles = {
    {0.8, 0.5},   // converging with spherical aberration, as a glass ball makes
    {0.8, 0.0},   // a perfect focus at alpha = 1.25
    {0.0, 0.0},   // collimated (alpha infinite)
    {-1.5, 0.0},  // diverging from a virtual focus behind the plane
    {2.0, 3.0},   // strongly focusing
    {1e-9, 1e6},  // alpha huge, beta huge: kappa beta z finite while kappa z vanishes
};

}  // namespace

// Every radius the solver returns, cast forward as that spot light's ray, meets the point (to 1e-9
// of the scene's scale); and the count agrees with a brute-force scan of s(r) = +-rho over a fine grid
// of radii (two roots closer than the grid step may be missed by the scan, never the solver).
TEST(CslEvaluation, EveryRadiusMeetsThePoint) {
  std::mt19937 random(3);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const double max_radius = 3.0;
  int checked = 0, scans_agreeing = 0, scans = 0;
  for (const Profile& profile : kProfiles) {
    for (int k = 0; k < 400; ++k) {
      const double z = 4.0 * uniform(random) + 1e-6, rho = 2.0 * uniform(random) + 1e-6;
      const Radii radii = profile.radii(z, rho, max_radius);
      for (int i = 0; i < radii.count; ++i) {
        const double r = radii.radius[i];
        ASSERT_GT(r, 0.0);
        ASSERT_LE(r, max_radius);
        // The ray from (side r, 0, 0) along a - g(r) (side r, 0, 0), at height z.
        const double x0 = radii.side[i] * r;
        const double slope = -profile.g(r) * x0;  // dx/dz
        const double x = x0 + slope * z;
        EXPECT_NEAR(x, rho, 1e-9 * std::max(1.0, std::fabs(slope) * z)) << "kappa " << profile.kappa << " z " << z;
        ++checked;
      }
      // Brute force: sign changes of s(r) - rho and s(r) + rho on a grid.
      int changes = 0;
      const int steps = 20000;
      for (int side : {+1, -1}) {
        double previous = profile.s(1e-12, z) - side * rho;
        for (int s = 1; s <= steps; ++s) {
          const double r = max_radius * s / steps;
          const double value = profile.s(r, z) - side * rho;
          if ((value > 0.0) != (previous > 0.0)) ++changes;
          previous = value;
        }
      }
      ++scans;
      if (changes == radii.count) ++scans_agreeing;
      EXPECT_GE(radii.count, changes) << "the solver missed a root the scan found";
    }
  }
  EXPECT_GT(checked, 1000);
  EXPECT_GT(scans_agreeing, 0.99 * scans);
}

// Eq. 4: sigma = |h h'| / r equals the ratio of the mapped annulus' area to the annulus' area,
// |s(r + dr)^2 - s(r - dr)^2| / ((r + dr)^2 - (r - dr)^2), as dr -> 0.
TEST(CslEvaluation, IntensityCorrectionIsTheDerivativeOfTheMappedArea) {
  for (const Profile& profile : kProfiles) {
    for (double r : {0.01, 0.3, 1.0, 2.5}) {
      for (double z : {0.05, 0.7, 1.3, 3.0}) {
        const double dr = 1e-6 * r;
        const double mapped = std::fabs(std::pow(profile.s(r + dr, z), 2) - std::pow(profile.s(r - dr, z), 2));
        const double numeric = mapped / (std::pow(r + dr, 2) - std::pow(r - dr, 2));
        EXPECT_NEAR(profile.area_ratio(r, z), numeric, 1e-5 * std::max(1.0, numeric))
            << "kappa " << profile.kappa << " beta " << profile.beta << " r " << r << " z " << z;
      }
    }
  }
}

// Closed forms: a collimated light gives its image's intensity times the cosine at any height; a
// perfect focus (beta = 0) concentrates it by 1 / (1 - z kappa)^2 before the focus.
TEST(CslEvaluation, CollimatedAndPerfectFocusAreExact) {
  const EvaluationSettings settings;
  const Vec3 facing(0.0f, 0.0f, -1.0f);
  float value[3] = {0.0f, 0.0f, 0.0f};
  const SpotLight collimated = uniform_light(0.0, 0.0, 2.0f, 2.5f);
  for (float z : {1e-6f, 0.5f, 40.0f}) {
    value[0] = 0.0f;
    collimated.evaluate(Vec3(0.7f, -0.3f, z), facing, 1e-3f, settings, value);
    EXPECT_NEAR(value[0], 2.5f, 1e-5f) << "z " << z;
  }
  // Tilted receiver: cos 60 degrees.
  value[0] = 0.0f;
  collimated.evaluate(Vec3(0.7f, -0.3f, 1.0f), glm::normalize(Vec3(std::sqrt(3.0f), 0.0f, -1.0f)), 1e-3f, settings, value);
  EXPECT_NEAR(value[0], 2.5f * 0.5f, 1e-5f);
  const SpotLight focus = uniform_light(0.8, 0.0, 2.0f, 1.0f);
  for (double z : {0.1, 0.6, 1.0}) {
    value[0] = 0.0f;
    const double rho = 0.2 * (1.0 - 0.8 * z);  // inside the cone of rays from r = 0.2
    focus.evaluate(Vec3(static_cast<float>(rho), 0.0f, static_cast<float>(z)), facing, 1e-4f, settings, value);
    // The ray meets the point at an angle: the receiver facing the axis takes |n.e| / |a.e| = 1.
    EXPECT_NEAR(value[0], 1.0 / std::pow(1.0 - 0.8 * z, 2), 1e-4 / std::pow(1.0 - 0.8 * z, 2)) << "z " << z;
  }
}

// Where the point values are finite on the axis (before the focal segment along it), the disk
// value of on_axis: integrate tends to them as the disk shrinks.
TEST(CslEvaluation, OnAxisValueIsTheLimitOfTheOffAxisValues) {
  const SpotLight light = uniform_light(0.8, 0.5, 2.0f, 1.0f, 512);
  // f(r) = 1.25 / (1 + 0.5 r) spans [0.555, 1.25] for r in [0, 2.83]: z = 0.3 is before every focus.
  const Vec3 facing(0.0f, 0.0f, -1.0f);
  EvaluationSettings settings;
  const double z = 0.3;
  float limit[3] = {0.0f, 0.0f, 0.0f};
  light.evaluate(Vec3(1e-4f, 0.0f, static_cast<float>(z)), facing, 0.0f, settings, limit);
  EXPECT_NEAR(limit[0], 1.0 / std::pow(1.0 - 0.8 * z, 2), 2e-3);
  for (float disk : {0.02f, 0.005f}) {
    float on_axis[3] = {0.0f, 0.0f, 0.0f};
    light.evaluate(Vec3(0.0f, 0.0f, static_cast<float>(z)), facing, disk, settings, on_axis);
    EXPECT_NEAR(on_axis[0], limit[0], 0.02 * limit[0]) << "disk " << disk;
  }
}

// In the focal segment the point values diverge like 1 / rho near the axis; the disk value is their
// average over the disk (integrated here by the midpoint rule in rho), which is finite.
TEST(CslEvaluation, OnAxisValueIsTheAverageOverTheFootprint) {
  const SpotLight light = uniform_light(0.8, 0.5, 2.0f, 1.0f, 512);
  const Vec3 facing(0.0f, 0.0f, -1.0f);
  EvaluationSettings settings;
  for (double z : {0.9, 1.1}) {
    const double disk = 0.05;
    float on_axis[3] = {0.0f, 0.0f, 0.0f};
    light.evaluate(Vec3(0.0f, 0.0f, static_cast<float>(z)), facing, static_cast<float>(disk), settings, on_axis);
    const int steps = 4000;
    double integral = 0.0;
    for (int i = 0; i < steps; ++i) {
      const double rho = disk * (i + 0.5) / steps;
      float value[3] = {0.0f, 0.0f, 0.0f};
      light.evaluate(Vec3(static_cast<float>(rho), 0.0f, static_cast<float>(z)), facing, 0.0f, settings, value);
      integral += value[0] * 2.0 * kPiDouble * rho * (disk / steps);
    }
    const double average = integral / (kPiDouble * disk * disk);
    EXPECT_TRUE(std::isfinite(on_axis[0]));
    EXPECT_NEAR(on_axis[0], average, 0.03 * average) << "z " << z;
    // The paper's epsilon instead gives a value that grows without bound as epsilon shrinks.
    EvaluationSettings paper;
    paper.on_axis = OnAxis::epsilon;
    float coarse[3] = {0.0f, 0.0f, 0.0f}, fine[3] = {0.0f, 0.0f, 0.0f};
    paper.axis_epsilon = 1e-3;
    light.evaluate(Vec3(0.0f, 0.0f, static_cast<float>(z)), facing, 0.0f, paper, coarse);
    paper.axis_epsilon = 1e-5;
    light.evaluate(Vec3(0.0f, 0.0f, static_cast<float>(z)), facing, 0.0f, paper, fine);
    EXPECT_GT(fine[0], 50.0f * coarse[0]) << "z " << z;
  }
}

// Finite and sane where the formulas degenerate: beta = 0, alpha huge, points exactly on the axis,
// z equal to alpha (every ray of a perfect focus meets there), z near 0, z negative (behind the plane).
TEST(CslEvaluation, ExtremesAreFiniteAndSane) {
  const Vec3 facing(0.0f, 0.0f, -1.0f);
  for (OnAxis mode : {OnAxis::integrate, OnAxis::epsilon}) {
    EvaluationSettings settings;
    settings.on_axis = mode;
    for (const Profile& profile : kProfiles) {
      const SpotLight light = uniform_light(profile.kappa, profile.beta);
      const double alpha = profile.kappa != 0.0 ? 1.0 / profile.kappa : 1e30;
      for (double z : {-1.0, 0.0, 1e-12, 1e-6, 0.5, alpha, 2.0 * std::fabs(alpha), 1e6}) {
        for (float rho : {0.0f, 1e-7f, 0.3f}) {
          float value[3] = {0.0f, 0.0f, 0.0f};
          light.evaluate(Vec3(rho, 0.0f, static_cast<float>(z)), facing, 1e-3f, settings, value);
          EXPECT_TRUE(std::isfinite(value[0])) << "kappa " << profile.kappa << " z " << z << " rho " << rho;
          EXPECT_GE(value[0], 0.0f);
          if (z <= 0.0) {
            EXPECT_EQ(value[0], 0.0f) << "behind the light plane";
          }
        }
      }
    }
  }
  // z near 0: the intensity of the image, uncorrected.
  const SpotLight light = uniform_light(0.8, 0.5);
  float value[3] = {0.0f, 0.0f, 0.0f};
  light.evaluate(Vec3(0.5f, 0.2f, 1e-7f), facing, 1e-4f, EvaluationSettings{}, value);
  EXPECT_NEAR(value[0], 1.0f, 1e-3f);
}

namespace {

// Rays of a known spot light: from points p of its plane along its rays e, each ray's origin moved
// forward along it by 0.3 to 0.6 (so that the rays start ahead of the plane, as exit points do).
std::vector<CausticRay> rays_of(const SpotLight& light, int per_side, double half) {
  std::vector<CausticRay> rays;
  for (int j = 0; j < per_side; ++j) {
    for (int i = 0; i < per_side; ++i) {
      const double x = -half + 2.0 * half * (i + 0.5) / per_side, y = -half + 2.0 * half * (j + 0.5) / per_side;
      if (x * x + y * y > half * half) continue;
      const Vec3 e = light.ray_direction(x, y);
      const Vec3 p = light.origin + static_cast<float>(x) * light.u + static_cast<float>(y) * light.v;
      const float forward = 0.3f + 0.3f * static_cast<float>((i * 7 + j * 13) % 17) / 16.0f;
      rays.push_back(CausticRay{p + forward * e, e, Color(1e-3f), 1e-3f});
    }
  }
  return rays;
}

}  // namespace

// A spot light's own rays are fitted back to it: alpha, beta and the light plane (Eq. 5 reaches ~0).
TEST(CslFit, RecoversAKnownSpotLight) {
  for (const Profile truth : {Profile{0.7, 0.4}, Profile{1.2, 0.0}, Profile{-0.8, 0.0}}) {
    SpotLight light;
    light.origin = Vec3(0.2f, -0.1f, 0.3f);
    light.axis = glm::normalize(Vec3(0.1f, -1.0f, 0.2f));
    set_plane_axes(light);
    light.profile = truth;
    const std::vector<CausticRay> rays = rays_of(light, 48, 0.5);
    std::vector<uint32_t> members(rays.size());
    for (uint32_t i = 0; i < members.size(); ++i) members[i] = i;
    // The bundle's axis: the true one, its origin shifted along it (the fit must find the plane).
    BundleAxis axis;
    axis.direction = glm::dvec3(light.axis);
    axis.origin = glm::dvec3(light.origin) + 0.9 * axis.direction;
    FitSettings settings;
    settings.reach = 8.0;
    settings.plane_range = 1.0;
    const Fit fit = fit_spot_light(rays, members, axis, settings);
    EXPECT_NEAR(fit.profile.beta, truth.beta, 1e-3 * truth.beta + 1e-5) << "kappa " << truth.kappa;
    EXPECT_LT(fit.final_cost, 1e-10 * std::max(1.0, fit.initial_cost)) << "kappa " << truth.kappa;
    if (truth.beta > 0.0) {
      // With beta > 0 the plane is determined: shifting it changes the profile's shape.
      EXPECT_NEAR(fit.profile.kappa, truth.kappa, 1e-4 * std::fabs(truth.kappa)) << "kappa " << truth.kappa;
      EXPECT_NEAR(glm::length(fit.origin - glm::dvec3(light.origin)), 0.0, 1e-4) << "kappa " << truth.kappa;
    } else {
      // With beta = 0 every plane along the axis describes the same lines: the focus is what is fixed.
      const glm::dvec3 focus = glm::dvec3(light.origin) + glm::dvec3(light.axis) / truth.kappa;
      const glm::dvec3 fitted = fit.origin + axis.direction / fit.profile.kappa;
      EXPECT_NEAR(glm::length(fitted - focus), 0.0, 1e-4) << "kappa " << truth.kappa;
    }
    for (const CausticRay& ray : rays) {
      EXPECT_LT(ray_on_plane(ray, axis, fit.ell, fit.profile).chord, 1e-5);
    }
  }
}

// A bundle of one ray, or of parallel rays, fits to something finite.
TEST(CslFit, DegenerateBundlesStayFinite) {
  std::vector<CausticRay> rays = {CausticRay{Vec3(0.0f, 0.0f, 1.0f), Vec3(0.0f, 0.0f, 1.0f), Color(1.0f), 1.0f}};
  BundleAxis axis;
  Fit fit = fit_spot_light(rays, {0}, axis, FitSettings{});
  EXPECT_TRUE(std::isfinite(fit.profile.kappa) && std::isfinite(fit.profile.beta) && std::isfinite(fit.ell));
  rays.clear();
  for (int i = 0; i < 10; ++i) rays.push_back(CausticRay{Vec3(0.1f * i, 0.0f, 0.0f), Vec3(0.0f, 0.0f, 1.0f), Color(1.0f), 1.0f});
  std::vector<uint32_t> members(rays.size());
  for (uint32_t i = 0; i < members.size(); ++i) members[i] = i;
  const BundleAxis parallel = optimise_axis(rays, members);
  EXPECT_NEAR(parallel.direction.z, 1.0, 1e-12);
  fit = fit_spot_light(rays, members, parallel, FitSettings{});
  EXPECT_NEAR(fit.profile.kappa, 0.0, 1e-6) << "parallel rays are collimated";
}

// Step 4: the lines of rays through one point give that point, and their mean direction.
TEST(CslBundles, AxisThroughTheCommonPointOfTheLines) {
  const glm::dvec3 focus(0.3, -0.2, 1.5);
  std::vector<CausticRay> rays;
  for (int i = 0; i < 50; ++i) {
    const double angle = 2.0 * kPiDouble * i / 50.0;
    const glm::dvec3 origin(0.5 * std::cos(angle), 0.5 * std::sin(angle), 0.0);
    rays.push_back(CausticRay{Vec3(origin), Vec3(glm::normalize(focus - origin)), Color(1.0f), 1.0f});
  }
  std::vector<uint32_t> members(rays.size());
  for (uint32_t i = 0; i < members.size(); ++i) members[i] = i;
  const BundleAxis axis = optimise_axis(rays, members);
  EXPECT_NEAR(glm::length(axis.origin - focus), 0.0, 1e-4);
  for (const CausticRay& ray : rays) EXPECT_NEAR(line_distance(ray, axis), 0.0, 1e-4);
}

// The DDA adds a ray's weight to every cell its line crosses: a line along x through the cube's
// interior crosses exactly `resolution` cells; a diagonal one at most 3 resolution - 2.
TEST(CslBundles, RasterCrossesTheRightCells) {
  RayRaster raster(Vec3(0.0f), 1.0, 16);
  raster.add(CausticRay{Vec3(5.0f, 0.03f, -0.41f), Vec3(-1.0f, 0.0f, 0.0f), Color(1.0f), 2.0f}, 1.0);
  double total = 0.0;
  for (int cell = 0; cell < 16 * 16 * 16; ++cell) total += raster.energy(cell);
  EXPECT_DOUBLE_EQ(total, 2.0 * 16);
  RayRaster diagonal(Vec3(0.0f), 1.0, 16);
  diagonal.add(CausticRay{Vec3(0.01f, 0.02f, 0.0f), glm::normalize(Vec3(1.0f, 1.1f, 0.9f)), Color(1.0f), 1.0f}, 1.0);
  total = 0.0;
  for (int cell = 0; cell < 16 * 16 * 16; ++cell) {
    glm::dvec3 low, high;
    diagonal.cell_box(cell, low, high);
    const bool crosses = line_crosses_box(CausticRay{Vec3(0.01f, 0.02f, 0.0f), glm::normalize(Vec3(1.0f, 1.1f, 0.9f)),
                                                     Color(1.0f), 1.0f},
                                          low, high);
    // Every cell with energy is crossed (cells merely touched at a corner may be skipped).
    if (diagonal.energy(cell) > 0.0) {
      EXPECT_TRUE(crosses) << cell;
    }
    total += diagonal.energy(cell);
  }
  EXPECT_GE(total, 16.0);
  EXPECT_LE(total, 3.0 * 16 - 2);
}

// The splat puts every ray's energy into the image once (float32: to rounding).
TEST(CslSplat, ConservesEnergy) {
  SpotLight light = uniform_light(0.6, 0.2);
  const std::vector<CausticRay> rays = rays_of(light, 40, 0.8);
  std::vector<uint32_t> members(rays.size());
  double energy = 0.0;
  for (uint32_t i = 0; i < members.size(); ++i) {
    members[i] = i;
    energy += rays[i].weight;
  }
  SplatSettings settings;
  settings.spacing = 1.6 / 40;
  settings.precision = IntensityImage::Precision::float32;
  const IntensityImage image = splat_intensity(rays, members, light, settings);
  double total = 0.0;
  image.total_flux(&total);
  EXPECT_NEAR(total, energy, 1e-4 * energy);
  EXPECT_TRUE(image.size() == 128 || image.size() == 256 || image.size() == 512);
  // uint16 keeps it to the quantisation step.
  settings.precision = IntensityImage::Precision::uint16;
  const IntensityImage quantised = splat_intensity(rays, members, light, settings);
  quantised.total_flux(&total);
  EXPECT_NEAR(total, energy, 2e-3 * energy);
}

// raster_extent (Section 3.1.1, step 1's extended bounding volume): the cube the rays' lines are counted
// in has half side raster_extent bounding radii about the object's centre. A line parallel to an axis
// crosses exactly `raster_resolution` cells of it when it passes inside, none when it passes outside;
// so a line 1.05 radii to the side of the centre is counted at raster_extent 1.1 and not at 1.0.
TEST(CslKnobs, RasterExtentIsTheHalfSideOfTheCubeTheRaysAreCountedIn) {
  const BoundingSphere bounds{Vec3(0.5f, 1.0f, -0.25f), 0.4f};
  auto counted = [&](double extent, float offset) {
    const ParamSet build = causticbench::testing::method_knobs(
                               "csl", {"raster_extent=" + std::to_string(extent), "raster_resolution=16"})
                               .build;
    const GenerateSettings settings = generate_settings(build, bounds, 0.01);
    EXPECT_DOUBLE_EQ(settings.bundle.raster_half_size, extent * bounds.radius);
    RayRaster raster(bounds.center, settings.bundle.raster_half_size, settings.bundle.raster_resolution);
    CausticRay ray;
    ray.origin = bounds.center + Vec3(-10.0f, offset * bounds.radius, 0.1f * bounds.radius);
    ray.direction = Vec3(1.0f, 0.0f, 0.0f);
    ray.weight = 0.25f;
    raster.add(ray, 1.0);
    double total = 0.0;
    int cells = 0;
    for (int cell = 0; cell < 16 * 16 * 16; ++cell) {
      total += raster.energy(cell);
      cells += raster.energy(cell) > 0.0;
    }
    EXPECT_DOUBLE_EQ(total, 0.25 * cells) << extent << " " << offset;
    return cells;
  };
  EXPECT_EQ(counted(1.0, 0.0f), 16);
  EXPECT_EQ(counted(1.0, 1.05f), 0);
  EXPECT_EQ(counted(1.1, 1.05f), 16);
  EXPECT_EQ(counted(4.0, 3.9f), 16);
  EXPECT_EQ(counted(4.0, 4.1f), 0);
}
