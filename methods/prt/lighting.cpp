#include "methods/prt/lighting.h"

#include <cmath>

namespace causticbench::prt {

bool rigid_rotation(const glm::mat3& linear, glm::dmat3& rotation) {
  const glm::dmat3 m(linear);
  const double scale = std::cbrt(std::abs(glm::determinant(m)));
  if (!(scale > 0.0)) return false;
  rotation = m / scale;
  const glm::dmat3 identity = glm::transpose(rotation) * rotation;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (std::abs(identity[i][j] - (i == j ? 1.0 : 0.0)) > 1e-5) return false;
  return glm::determinant(rotation) > 0.0;
}

const std::vector<glm::dvec3>& LightingProjector::world_coefficients(const LightFrame& light, size_t& projected_points) {
  const auto key = std::make_tuple(light.light, light.direction_to_light.x, light.direction_to_light.y, light.direction_to_light.z);
  auto found = cache_.find(key);
  if (found != cache_.end()) return found->second;
  const EnvironmentQuadrature quadrature = environment_quadrature(light, harmonic_quadrature_angle(bands_));
  projected_points += quadrature.directions.size();
  return cache_.emplace(key, harmonic_weights(bands_, quadrature, glm::mat3(1.0f))).first->second;
}

FrameLighting LightingProjector::project(const std::vector<LightFrame>& lights, const BuildSpaceMap& map,
                                         const Vec3& build_center, HarmonicWindow window) {
  FrameLighting lighting;
  const size_t count = static_cast<size_t>(coefficient_count(bands_));
  for (std::vector<double>& channel : lighting.coefficients) channel.assign(count, 0.0);
  glm::dmat3 rotation;
  const bool rigid = rigid_rotation(map.linear, rotation);
  for (const LightFrame& light : lights) {
    std::vector<glm::dvec3> coefficients;
    if (is_environment_light(light.kind)) {
      if (rigid) {
        const std::vector<glm::dvec3>& world = world_coefficients(light, lighting.quadrature_points);
        const HarmonicRotation turn(bands_, rotation);
        coefficients.assign(count, glm::dvec3(0.0));
        for (int c = 0; c < 3; ++c) {
          std::vector<double> channel(count);
          for (size_t k = 0; k < count; ++k) channel[k] = world[k][c];
          const std::vector<double> turned = turn.apply(channel);
          for (size_t k = 0; k < count; ++k) coefficients[k][c] = turned[k];
        }
      } else {
        const EnvironmentQuadrature quadrature = environment_quadrature(light, harmonic_quadrature_angle(bands_));
        lighting.quadrature_points += quadrature.directions.size();
        coefficients = harmonic_weights(bands_, quadrature, map.linear);
      }
    } else {
      const ObjectLight seen = object_light(map, light, build_center);
      if (!seen.valid) continue;  // a point light at the centre has no direction
      double basis[kMaxBands * kMaxBands];
      evaluate(bands_, glm::dvec3(seen.direction), basis);
      coefficients.assign(count, glm::dvec3(0.0));
      for (size_t k = 0; k < count; ++k) coefficients[k] = glm::dvec3(seen.irradiance) * basis[k];
    }
    for (size_t k = 0; k < count; ++k)
      for (int c = 0; c < 3; ++c) lighting.coefficients[c][k] += coefficients[k][c];
  }
  for (std::vector<double>& channel : lighting.coefficients) apply_window(window, bands_, channel);
  return lighting;
}

}  // namespace causticbench::prt
