#include "methods/rt_photons/emission.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/low_discrepancy.h"

namespace causticbench::rt_photons {

namespace {

// The six faces of a cube: axis, then u and v with u x v = axis.
const Vec3 kFaceAxis[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
const Vec3 kFaceU[6] = {{0, 1, 0}, {0, 0, 1}, {0, 0, 1}, {1, 0, 0}, {1, 0, 0}, {0, 1, 0}};

// The objects' middle: the mean of their bounding spheres' centres.
Vec3 objects_middle(const std::vector<BoundingSphere>& targets) {
  Vec3 middle(0.0f);
  for (const BoundingSphere& target : targets) middle += target.center / static_cast<float>(targets.size());
  return middle;
}

// A point's grid: the six faces of a unit cube around `position`. Photons leaving a sphere of radius
// `reach` about it reach a target from any of its points: the test widens by it.
EmissionGrid point_grid(const Vec3& position, float reach, const std::vector<BoundingSphere>& targets, int resolution) {
  EmissionGrid grid;
  grid.kind = LightKind::point;
  grid.origin = position;
  grid.resolution = resolution;
  grid.faces = 6;
  grid.texel = 2.0f / static_cast<float>(resolution);
  grid.active.assign(6 * static_cast<size_t>(resolution) * resolution, 0);
  for (int face = 0; face < 6; ++face) {
    const Vec3 u = kFaceU[face], v = glm::cross(kFaceAxis[face], u);
    grid.axis_u.push_back(u);
    grid.axis_v.push_back(v);
    grid.corner.push_back(kFaceAxis[face] - u - v);
    for (int j = 0; j < resolution; ++j)
      for (int i = 0; i < resolution; ++i) {
        const Vec3 centre = grid.corner[face] + (static_cast<float>(i) + 0.5f) * grid.texel * u +
                            (static_cast<float>(j) + 0.5f) * grid.texel * v;
        const Vec3 direction = glm::normalize(centre);
        // The texel's bundle: within its half-diagonal's angle of its centre direction (on the cube a
        // texel subtends at most that).
        const float half_angle = std::atan(0.7072f * grid.texel / glm::length(centre));
        bool reaches = false;
        for (const BoundingSphere& target : targets) {
          const Vec3 to = target.center - position;
          const float distance = glm::length(to);
          if (distance <= target.radius + reach) {
            reaches = true;
            break;
          }
          const float angle = std::acos(std::clamp(glm::dot(direction, to / distance), -1.0f, 1.0f));
          if (angle <= std::asin((target.radius + reach) / distance) + half_angle) {
            reaches = true;
            break;
          }
        }
        grid.active[(static_cast<size_t>(face) * resolution + j) * resolution + i] = reaches;
      }
  }
  return grid;
}

// A distant direction's grid: the plane across the beam travelling away from `direction_to_light`. Photons
// travelling up to `spread` radians off it (a sun's disk) reach each target from a wider patch: its disk
// widens by its distance from the plane times tan(spread).
EmissionGrid directional_grid(const Vec3& direction_to_light, float spread, const std::vector<BoundingSphere>& input_targets,
                              const BoundingSphere& scene, int resolution) {
  EmissionGrid grid;
  grid.kind = LightKind::directional;
  grid.resolution = resolution;
  const Vec3 to_light = glm::normalize(direction_to_light);
  grid.travel = -to_light;
  const float back = glm::dot(scene.center, to_light) + scene.radius * 1.01f;
  std::vector<BoundingSphere> targets = input_targets;
  for (BoundingSphere& target : targets)
    target.radius += std::max(0.0f, back - glm::dot(target.center, to_light) + target.radius) * std::tan(spread);
  Vec3 u, v;
  orthonormal_basis(to_light, u, v);
  float lower_u = 1e30f, lower_v = 1e30f, upper_u = -1e30f, upper_v = -1e30f;
  for (const BoundingSphere& target : targets) {
    lower_u = std::min(lower_u, glm::dot(target.center, u) - target.radius);
    lower_v = std::min(lower_v, glm::dot(target.center, v) - target.radius);
    upper_u = std::max(upper_u, glm::dot(target.center, u) + target.radius);
    upper_v = std::max(upper_v, glm::dot(target.center, v) + target.radius);
  }
  const float side = std::max(upper_u - lower_u, upper_v - lower_v);
  grid.texel = side / static_cast<float>(resolution);
  grid.corner.push_back(lower_u * u + lower_v * v + back * to_light);
  grid.through = std::max(0.0f, back - glm::dot(objects_middle(input_targets), to_light));
  grid.axis_u.push_back(u);
  grid.axis_v.push_back(v);
  grid.active.assign(static_cast<size_t>(resolution) * resolution, 0);
  for (int j = 0; j < resolution; ++j)
    for (int i = 0; i < resolution; ++i) {
      const float cu = lower_u + (static_cast<float>(i) + 0.5f) * grid.texel;
      const float cv = lower_v + (static_cast<float>(j) + 0.5f) * grid.texel;
      bool reaches = false;
      for (const BoundingSphere& target : targets) {
        const float du = std::max(std::abs(cu - glm::dot(target.center, u)) - 0.5f * grid.texel, 0.0f);
        const float dv = std::max(std::abs(cv - glm::dot(target.center, v)) - 0.5f * grid.texel, 0.0f);
        if (du * du + dv * dv <= target.radius * target.radius) reaches = true;
      }
      grid.active[static_cast<size_t>(j) * resolution + i] = reaches;
    }
  return grid;
}

}  // namespace

bool is_delta_light(const LightFrame& light) {
  return (light.kind == LightKind::directional && light.cos_cone >= 1.0f) || (light.kind == LightKind::point && light.radius <= 0.0f);
}

std::vector<EmissionGrid> emission_grids(const LightFrame& light, size_t light_index, const std::vector<BoundingSphere>& targets,
                                         const BoundingSphere& scene, int resolution, int light_samples, uint64_t sample_seed) {
  std::vector<EmissionGrid> grids;
  if (targets.empty()) return grids;
  const int samples = is_delta_light(light) ? 1 : std::max(1, light_samples);
  const ShiftedSobol points(sample_seed, light_index);
  auto draw = [&](int k, int dimension) { return points.uniform(static_cast<uint32_t>(k), dimension); };
  // One map shared by the samples, where the light's blur moves a photon at the objects by less than a
  // texel (a sun's disk, a small sphere light): each photon takes one sample, and the map keeps its
  // stratification. Otherwise (an environment, a Gaussian spot, a wide disk or sphere) each sample its own
  // map: a plane of resolution / sqrt(K) a side, so that the light's texels in all stay about
  // resolution^2 (K planes of the full resolution would leave most texels one photon or none, and
  // emission its stratification), a cube at the full resolution (below); a disk's, a spot's or a
  // sphere's maps overlap (EmissionGrid::overlapping).
  if (light.kind == LightKind::point) {
    // A sphere light's samples leave from its surface: the map's reach widens by its radius then.
    EmissionGrid grid = point_grid(light.position, samples > 1 ? light.radius : 0.0f, targets, resolution);
    grid.emitted = light.light->intensity;
    float nearest = std::numeric_limits<float>::infinity();
    for (const BoundingSphere& target : targets) nearest = std::min(nearest, glm::length(target.center - light.position) - target.radius);
    if (samples == 1 || light.radius <= grid.texel * std::max(0.0f, nearest)) {
      if (samples > 1)
        for (int k = 0; k < samples; ++k) {
          grid.sample_origin.push_back(light.sample_position(draw(k, 0), draw(k, 1)));
          grid.sample_emitted.push_back(light.light->intensity);
        }
      grids.push_back(std::move(grid));
    }
  } else if (light.kind == LightKind::directional) {
    const float spread = samples > 1 ? std::acos(std::clamp(light.cos_cone, -1.0f, 1.0f)) : 0.0f;
    EmissionGrid grid = directional_grid(light.direction_to_light, spread, targets, scene, resolution);
    grid.emitted = light.light->irradiance;
    // How far a photon through the plane of the objects' middle strays at the objects: their depth about
    // that plane times tan(spread).
    const Vec3 middle = objects_middle(targets), to_light = glm::normalize(light.direction_to_light);
    float depth = 0.0f;
    for (const BoundingSphere& target : targets)
      depth = std::max(depth, std::abs(glm::dot(target.center - middle, to_light)) + target.radius);
    if (samples == 1 || depth * std::tan(spread) <= grid.texel) {
      if (samples > 1)
        for (int k = 0; k < samples; ++k) {
          Color weight(0.0f);
          grid.sample_travel.push_back(-light.sample_direction(draw(k, 0), draw(k, 1), draw(k, 2), weight));
          grid.sample_emitted.push_back(weight);
        }
      grids.push_back(std::move(grid));
    }
  }
  if (grids.empty()) {
    // A plane across a beam covers only the objects, so a coarser one wastes no photon; a point's cube
    // covers every direction, and coarser texels would send most of theirs past a small or distant object
    // (a sphere light 100 units off at 8 texels a face: relMSE 11 against 0.05): it keeps its resolution.
    const int sample_resolution =
        samples == 1 ? resolution : std::max(4, static_cast<int>(std::lround(resolution / std::sqrt(double(samples)))));
    for (int k = 0; k < samples; ++k) {
      EmissionGrid grid;
      if (light.kind == LightKind::point) {
        grid = point_grid(light.sample_position(draw(k, 0), draw(k, 1)), 0.0f, targets, resolution);
        grid.emitted = light.light->intensity / static_cast<float>(samples);
        grid.overlapping = samples;
      } else {
        Color weight(0.0f);
        const Vec3 to_light = light.sample_direction(draw(k, 0), draw(k, 1), draw(k, 2), weight);
        if (!(max_component(weight) > 0.0f) || !std::isfinite(max_component(weight))) continue;
        grid = directional_grid(to_light, 0.0f, targets, scene, sample_resolution);
        grid.emitted = weight / static_cast<float>(samples);
        if (light.kind != LightKind::environment_image) grid.overlapping = samples;
      }
      grids.push_back(std::move(grid));
    }
  }
  for (EmissionGrid& grid : grids) grid.light = light_index, grid.samples = samples;
  return grids;
}

namespace {

// A texel's face and its coordinates (u, v) on the face of the point at fractions (s, t).
void texel_point(const EmissionGrid& grid, size_t texel, float s, float t, int& face, float& u, float& v) {
  const size_t per_face = static_cast<size_t>(grid.resolution) * grid.resolution;
  face = static_cast<int>(texel / per_face);
  const size_t within = texel % per_face;
  u = (static_cast<float>(within % grid.resolution) + s) * grid.texel;
  v = (static_cast<float>(within / grid.resolution) + t) * grid.texel;
}

}  // namespace

double texel_flux(const EmissionGrid& grid, size_t texel) {
  if (grid.kind != LightKind::point) return luminance(grid.emitted) * double(grid.texel) * grid.texel;
  // The solid angle of a cube-face rectangle [x0, x1] x [y0, y1] at unit distance: the sum of the corners'
  // atan(x y / sqrt(1 + x^2 + y^2)) with alternating signs.
  int face;
  float u, v;
  texel_point(grid, texel, 0.0f, 0.0f, face, u, v);
  const double x0 = u - 1.0, y0 = v - 1.0, x1 = x0 + grid.texel, y1 = y0 + grid.texel;
  auto corner = [](double x, double y) { return std::atan(x * y / std::sqrt(1.0 + x * x + y * y)); };
  const double solid_angle = corner(x1, y1) - corner(x0, y1) - corner(x1, y0) + corner(x0, y0);
  return luminance(grid.emitted) * solid_angle;
}

void emit_photon(const EmissionGrid& grid, size_t texel, float s, float t, float pick, double share, Ray& ray, Color& power,
                 RayDifferential& differential) {
  const size_t sample_count = grid.sample_emitted.size();
  const size_t sample = sample_count > 0 ? std::min(sample_count - 1, static_cast<size_t>(pick * static_cast<float>(sample_count))) : 0;
  int face;
  float u, v;
  texel_point(grid, texel, s, t, face, u, v);
  ray.t_min = 0.0f;
  ray.t_max = 1e30f;
  const double area = double(grid.texel) * grid.texel * share;  // the photon's patch of the texel
  if (grid.kind != LightKind::point) {
    ray.origin = grid.corner[0] + u * grid.axis_u[0] + v * grid.axis_v[0];
    ray.direction = grid.travel;
    power = grid.emitted * static_cast<float>(area);
    if (sample_count > 0) {
      // The sample's beam crosses the map's plane at an angle: its irradiance there is E cos.
      // ... and passes through its point on the plane through the objects (where the photons keep their
      // stratification; a start on the map's own plane, metres behind, moved them by more than their
      // spacing through the water pool's surface, and the caustic turned to noise).
      ray.direction = grid.sample_travel[sample];
      ray.origin += grid.travel * grid.through - ray.direction * grid.through;
      power = grid.sample_emitted[sample] * static_cast<float>(area * std::max(0.0f, glm::dot(ray.direction, grid.travel)));
    }
    differential = RayDifferential{grid.axis_u[0], grid.axis_v[0], Vec3(0.0f), Vec3(0.0f)};
    return;
  }
  const Vec3 on_cube = grid.corner[face] + u * grid.axis_u[face] + v * grid.axis_v[face];
  const float length = glm::length(on_cube);
  const Vec3 direction = on_cube / length;
  ray.origin = sample_count > 0 ? grid.sample_origin[sample] : grid.origin;
  ray.direction = direction;
  // d omega = dA cos / r^2 on the face at unit distance: dA / length^3.
  power = grid.emitted * static_cast<float>(area / (double(length) * length * length));
  differential.dp_du = differential.dp_dv = Vec3(0.0f);
  differential.dd_du = (grid.axis_u[face] - direction * glm::dot(direction, grid.axis_u[face])) / length;
  differential.dd_dv = (grid.axis_v[face] - direction * glm::dot(direction, grid.axis_v[face])) / length;
}

}  // namespace causticbench::rt_photons
