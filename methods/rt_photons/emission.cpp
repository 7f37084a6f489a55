#include "methods/rt_photons/emission.h"

#include <algorithm>
#include <cmath>

namespace causticbench::rt_photons {

namespace {

// The six faces of a cube: axis, then u and v with u x v = axis.
const Vec3 kFaceAxis[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
const Vec3 kFaceU[6] = {{0, 1, 0}, {0, 0, 1}, {0, 0, 1}, {1, 0, 0}, {1, 0, 0}, {0, 1, 0}};

}  // namespace

EmissionGrid emission_grid(const LightFrame& light, const std::vector<BoundingSphere>& targets,
                           const BoundingSphere& scene, int resolution) {
  EmissionGrid grid;
  grid.kind = light.kind;
  grid.light = &light;
  grid.resolution = resolution;
  if (targets.empty() || light.kind == LightKind::environment_image || light.kind == LightKind::gaussian_spot)
    return grid;
  if (light.kind == LightKind::point) {
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
            const Vec3 to = target.center - light.position;
            const float distance = glm::length(to);
            if (distance <= target.radius) {
              reaches = true;
              break;
            }
            const float angle = std::acos(std::clamp(glm::dot(direction, to / distance), -1.0f, 1.0f));
            if (angle <= std::asin(target.radius / distance) + half_angle) {
              reaches = true;
              break;
            }
          }
          grid.active[(static_cast<size_t>(face) * resolution + j) * resolution + i] = reaches;
        }
    }
    return grid;
  }
  // A distant light: the plane across the beam.
  const Vec3 to_light = glm::normalize(light.direction_to_light);
  grid.travel = -to_light;
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
  const float back = glm::dot(scene.center, to_light) + scene.radius * 1.01f;
  grid.corner.push_back(lower_u * u + lower_v * v + back * to_light);
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
  if (grid.kind != LightKind::point) return luminance(grid.light->light->irradiance) * double(grid.texel) * grid.texel;
  // The solid angle of a cube-face rectangle [x0, x1] x [y0, y1] at unit distance: the sum of the corners'
  // atan(x y / sqrt(1 + x^2 + y^2)) with alternating signs.
  int face;
  float u, v;
  texel_point(grid, texel, 0.0f, 0.0f, face, u, v);
  const double x0 = u - 1.0, y0 = v - 1.0, x1 = x0 + grid.texel, y1 = y0 + grid.texel;
  auto corner = [](double x, double y) { return std::atan(x * y / std::sqrt(1.0 + x * x + y * y)); };
  const double solid_angle = corner(x1, y1) - corner(x0, y1) - corner(x1, y0) + corner(x0, y0);
  return luminance(grid.light->light->intensity) * solid_angle;
}

void emit_photon(const EmissionGrid& grid, size_t texel, float s, float t, double share, Ray& ray, Color& power,
                 RayDifferential& differential) {
  int face;
  float u, v;
  texel_point(grid, texel, s, t, face, u, v);
  ray.t_min = 0.0f;
  ray.t_max = 1e30f;
  const double area = double(grid.texel) * grid.texel * share;  // the photon's patch of the texel
  if (grid.kind != LightKind::point) {
    ray.origin = grid.corner[0] + u * grid.axis_u[0] + v * grid.axis_v[0];
    ray.direction = grid.travel;
    power = grid.light->light->irradiance * static_cast<float>(area);
    differential = RayDifferential{grid.axis_u[0], grid.axis_v[0], Vec3(0.0f), Vec3(0.0f)};
    return;
  }
  const Vec3 on_cube = grid.corner[face] + u * grid.axis_u[face] + v * grid.axis_v[face];
  const float length = glm::length(on_cube);
  const Vec3 direction = on_cube / length;
  ray.origin = grid.light->position;
  ray.direction = direction;
  // d omega = dA cos / r^2 on the face at unit distance: dA / length^3.
  power = grid.light->light->intensity * static_cast<float>(area / (double(length) * length * length));
  differential.dp_du = differential.dp_dv = Vec3(0.0f);
  differential.dd_du = (grid.axis_u[face] - direction * glm::dot(direction, grid.axis_u[face])) / length;
  differential.dd_dv = (grid.axis_v[face] - direction * glm::dot(direction, grid.axis_v[face])) / length;
}

}  // namespace causticbench::rt_photons
