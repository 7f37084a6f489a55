#include "methods/lpi/environment.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/parallel.h"

namespace causticbench::lpi {

double hat_quadrature_angle(const SphericalMesh& mesh) {
  double longest = 0.0;
  const std::vector<Vec3>& points = mesh.points();
  for (const auto& triangle : mesh.triangles()) {
    for (int e = 0; e < 3; ++e) {
      const double cosine = glm::dot(glm::dvec3(points[triangle[e]]), glm::dvec3(points[triangle[(e + 1) % 3]]));
      longest = std::max(longest, std::acos(std::clamp(cosine, -1.0, 1.0)));
    }
  }
  return longest / 8.0;
}

std::vector<glm::dvec3> hat_weights(const SphericalMesh& mesh, const EnvironmentQuadrature& quadrature,
                                    const glm::mat3& to_build) {
  const auto& triangles = mesh.triangles();
  return chunked_sum(quadrature.directions.size(), mesh.points().size(), [&](size_t i, std::vector<glm::dvec3>& sums) {
    const SphericalMesh::Location location = mesh.locate(glm::normalize(to_build * quadrature.directions[i]));
    for (int corner = 0; corner < 3; ++corner) {
      sums[triangles[location.triangle][corner]] += quadrature.irradiance[i] * static_cast<double>(location.weights[corner]);
    }
  });
}

StoredValues combine_blocks(const StoredValues& values, const std::vector<glm::dvec3>& weights) {
  if (weights.size() != values.light_samples()) {
    throw std::logic_error("combine_blocks: one weight per block of stored values");
  }
  const int channels = values.channels();
  const int per_colour = channels / 3;  // 1 (paper) or 3 (vector)
  std::vector<size_t> used;
  for (size_t b = 0; b < weights.size(); ++b) {
    if (weights[b] != glm::dvec3(0.0)) used.push_back(b);
  }
  std::vector<float> combined(values.points() * static_cast<size_t>(channels), 0.0f);
  parallel_blocks(values.points(), 4096, [&](size_t begin, size_t end, size_t) {
    for (size_t point = begin; point < end; ++point) {
      double sums[9] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
      for (size_t b : used) {
        float read[9] = {0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f};
        values.add(b, point, 1.0f, read);
        for (int c = 0; c < channels; ++c) sums[c] += weights[b][c / per_colour] * read[c];
      }
      for (int c = 0; c < channels; ++c) combined[point * channels + c] = static_cast<float>(sums[c]);
    }
  });
  return StoredValues::encode(Precision::float32, channels, true, values.points(), combined);
}

}  // namespace causticbench::lpi
