#include "methods/common/environment_quadrature.h"

#include <cmath>
#include <stdexcept>

#include "methods/common/spherical_harmonics.h"

namespace causticbench {

glm::dvec3 EnvironmentQuadrature::total() const {
  glm::dvec3 sum(0.0);
  for (const glm::dvec3& value : irradiance) sum += value;
  return sum;
}

namespace {

void add_point(EnvironmentQuadrature& quadrature, const Vec3& direction, const glm::dvec3& irradiance) {
  if (!(irradiance.x > 0.0 || irradiance.y > 0.0 || irradiance.z > 0.0)) return;
  quadrature.directions.push_back(direction);
  quadrature.irradiance.push_back(irradiance);
}

void image_quadrature(const EnvironmentMap& map, double cell_angle, EnvironmentQuadrature& quadrature) {
  const double texel_size = std::max(2.0 * kPiDouble / map.width(), kPiDouble / map.height());
  const int cuts = std::max(1, static_cast<int>(std::ceil(texel_size / cell_angle)));
  for (int y = 0; y < map.height(); ++y) {
    const double cell_solid_angle = map.texel_solid_angle(y) / (cuts * cuts);
    for (int x = 0; x < map.width(); ++x) {
      const glm::dvec3 radiance(map.texel(x, y));
      if (!(radiance.x > 0.0 || radiance.y > 0.0 || radiance.z > 0.0)) continue;
      for (int j = 0; j < cuts; ++j) {
        for (int i = 0; i < cuts; ++i) {
          add_point(quadrature, map.texel_direction(x, y, (i + 0.5) / cuts, (j + 0.5) / cuts), radiance * cell_solid_angle);
        }
      }
    }
  }
}

// The spot's radiance E exp(-theta^2 / 2 sigma^2) / (2 pi sigma^2), as the reference samples it
// (core/light.cpp: radiance / pdf = E sin(theta) / theta for the Rayleigh draw).
void spot_quadrature(const LightFrame& light, double cell_angle, EnvironmentQuadrature& quadrature) {
  const double sigma = light.spot_sigma;
  const glm::dvec3 irradiance(light.light->irradiance);
  // Beyond theta_t the spot holds exp(-theta_t^2 / 2 sigma^2) of its power: 1e-6.
  const double cutoff = std::min(kPiDouble, sigma * std::sqrt(2.0 * std::log(1e6)));
  const double ring_width = std::min(sigma / 8.0, cell_angle);
  const int rings = std::max(1, static_cast<int>(std::ceil(cutoff / ring_width)));
  const double width = cutoff / rings;
  auto radial = [&](double theta) {
    return std::exp(-theta * theta / (2.0 * sigma * sigma)) / (2.0 * kPiDouble * sigma * sigma) * std::sin(theta);
  };
  Vec3 tangent, bitangent;
  const Vec3 axis = glm::normalize(light.direction_to_light);
  orthonormal_basis(axis, tangent, bitangent);
  for (int ring = 0; ring < rings; ++ring) {
    const double inner = ring * width, outer = (ring + 1) * width, middle = 0.5 * (inner + outer);
    // The ring's integral of L sin(theta) d theta by Simpson's rule, shared among its azimuth cells.
    const double ring_integral = width / 6.0 * (radial(inner) + 4.0 * radial(middle) + radial(outer));
    const int cells = std::max(8, static_cast<int>(std::ceil(2.0 * kPiDouble * std::sin(std::min(outer, kPiDouble / 2)) /
                                                             cell_angle)));
    const double cell_weight = ring_integral * 2.0 * kPiDouble / cells;
    const double sin_theta = std::sin(middle), cos_theta = std::cos(middle);
    for (int cell = 0; cell < cells; ++cell) {
      const double phi = 2.0 * kPiDouble * (cell + 0.5) / cells;
      const Vec3 direction = glm::normalize(axis * static_cast<float>(cos_theta) +
                                            (tangent * static_cast<float>(std::cos(phi)) +
                                             bitangent * static_cast<float>(std::sin(phi))) *
                                                static_cast<float>(sin_theta));
      add_point(quadrature, direction, irradiance * cell_weight);
    }
  }
}

}  // namespace

EnvironmentQuadrature environment_quadrature(const LightFrame& light, double cell_angle) {
  if (!(cell_angle > 0.0)) throw std::invalid_argument("environment_quadrature: cell_angle must be positive");
  EnvironmentQuadrature quadrature;
  if (light.kind == LightKind::environment_image) {
    image_quadrature(*light.light->environment, cell_angle, quadrature);
  } else if (light.kind == LightKind::gaussian_spot) {
    spot_quadrature(light, cell_angle, quadrature);
  } else {
    throw std::invalid_argument("environment_quadrature: not an environment light");
  }
  return quadrature;
}

double harmonic_quadrature_angle(int bands) { return kPiDouble / std::max(1, bands) / 16.0; }

std::vector<glm::dvec3> harmonic_weights(int bands, const EnvironmentQuadrature& quadrature, const glm::mat3& to_build) {
  const int count = coefficient_count(bands);
  return chunked_sum(quadrature.directions.size(), static_cast<size_t>(count), [&](size_t i, std::vector<glm::dvec3>& sums) {
    double basis[kMaxBands * kMaxBands];
    evaluate(bands, glm::normalize(glm::dvec3(to_build * quadrature.directions[i])), basis);
    for (int k = 0; k < count; ++k) sums[k] += quadrature.irradiance[i] * basis[k];
  });
}

}  // namespace causticbench
