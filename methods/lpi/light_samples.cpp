#include "methods/lpi/light_samples.h"

#include <cmath>

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>

namespace causticbench::lpi {

LightSampleSet geodesic_samples(int level, SampleAt at) {
  LightSampleSet set;
  set.kind = "geodesic";
  set.mesh = at == SampleAt::vertices ? SphericalMesh::geodesic_vertices(level) : SphericalMesh::geodesic_face_centers(level);
  set.directions = set.mesh->points();
  return set;
}

LightSampleSet geodesic_part(LightSampleSet geodesic, const std::vector<bool>& keep) {
  LightSampleSet part;
  part.kind = "environment";
  part.mesh = std::move(geodesic.mesh);
  part.sample_of_point.assign(part.mesh->points().size(), -1);
  for (uint32_t point = 0; point < part.mesh->points().size(); ++point) {
    if (!keep[point]) continue;
    part.sample_of_point[point] = static_cast<int32_t>(part.directions.size());
    part.mesh_points.push_back(point);
    part.directions.push_back(part.mesh->points()[point]);
  }
  return part;
}

LightSampleSet meridian_samples(int level, const Vec3& axis) {
  LightSampleSet set;
  set.kind = "meridian";
  set.axis = glm::normalize(axis);
  Vec3 tangent, bitangent;
  orthonormal_basis(set.axis, tangent, bitangent);
  set.meridian = tangent;
  const int count = 5 * (1 << level) + 1;
  for (int m = 0; m < count; ++m) {
    const double theta = kPiDouble * m / (count - 1);
    set.directions.push_back(glm::normalize(set.axis * static_cast<float>(std::cos(theta)) +
                                            set.meridian * static_cast<float>(std::sin(theta))));
  }
  return set;
}

glm::mat3 rotation_between(const Vec3& from, const Vec3& to) {
  const float cosine = std::clamp(glm::dot(from, to), -1.0f, 1.0f);
  Vec3 axis = glm::cross(from, to);
  const float sine = glm::length(axis);
  if (sine < 1e-7f) {
    if (cosine > 0.0f) return glm::mat3(1.0f);
    Vec3 tangent, bitangent;
    orthonormal_basis(from, tangent, bitangent);
    axis = tangent;
  } else {
    axis /= sine;
  }
  const float angle = std::atan2(sine, cosine);
  return glm::mat3(glm::rotate(glm::mat4(1.0f), angle, axis));
}

namespace {

uint32_t nearest_direction(const std::vector<Vec3>& directions, const Vec3& direction) {
  uint32_t best = 0;
  float best_dot = -2.0f;
  for (uint32_t i = 0; i < directions.size(); ++i) {
    const float dot = glm::dot(directions[i], direction);
    if (dot > best_dot) {
      best_dot = dot;
      best = i;
    }
  }
  return best;
}

// A zero weight reads nothing: a light exactly on a sample reads that sample alone.
void add_read(LightReads& reads, uint32_t sample, float weight, const glm::mat3& rotation, bool rotated) {
  if (!(weight > 0.0f)) return;
  SampleRead& read = reads.reads[reads.count++];
  read.sample = sample;
  read.weight = weight;
  read.rotation = rotation;
  read.rotated = rotated;
}

}  // namespace

LightReads light_reads(const LightSampleSet& set, const Vec3& direction, Blend blend) {
  LightReads reads;
  if (set.kind == "static") {
    add_read(reads, nearest_direction(set.directions, direction), 1.0f, glm::mat3(1.0f), false);
    return reads;
  }
  if (set.kind == "spherical") {
    glm::mat3 rotation = rotation_between(direction, set.directions[0]);
    add_read(reads, 0, 1.0f, rotation, true);
    return reads;
  }
  if (set.kind == "meridian") {
    // Turn about the axis into the meridian's half-plane (exact for an axially symmetric object).
    const Vec3 across = glm::cross(set.axis, set.meridian);
    const float azimuth = std::atan2(glm::dot(direction, across), glm::dot(direction, set.meridian));
    const glm::mat3 turn(glm::rotate(glm::mat4(1.0f), -azimuth, set.axis));
    const Vec3 in_plane = glm::normalize(turn * direction);
    const int intervals = static_cast<int>(set.directions.size()) - 1;
    const float polar = std::acos(std::clamp(glm::dot(in_plane, set.axis), -1.0f, 1.0f));
    const float position = polar / kPi * static_cast<float>(intervals);
    const int lower = std::clamp(static_cast<int>(position), 0, intervals - 1);
    const float fraction = std::clamp(position - static_cast<float>(lower), 0.0f, 1.0f);
    if (blend == Blend::nearest) {
      add_read(reads, fraction < 0.5f ? lower : lower + 1, 1.0f, turn, true);
      return reads;
    }
    for (int corner = 0; corner < 2; ++corner) {
      const uint32_t sample = static_cast<uint32_t>(lower + corner);
      const float weight = corner ? fraction : 1.0f - fraction;
      const glm::mat3 rotation =
          blend == Blend::aligned ? rotation_between(in_plane, set.directions[sample]) * turn : turn;
      add_read(reads, sample, weight, rotation, true);
    }
    if (reads.count == 0) add_read(reads, static_cast<uint32_t>(lower), 1.0f, turn, true);
    return reads;
  }
  // The geodesic set.
  // The geodesic set, or the part of it an environment light needs (whose plan holds every sample
  // a fixed directional light reads: a left-out point reads nothing).
  if (blend == Blend::nearest) {
    const int32_t sample = set.sample_of(set.mesh->nearest_point(direction));
    if (sample >= 0) add_read(reads, static_cast<uint32_t>(sample), 1.0f, glm::mat3(1.0f), false);
    return reads;
  }
  const SphericalMesh::Location location = set.mesh->locate(direction);
  // Weights sum to one, so one of them is positive; rounding cannot leave all three at zero.
  const auto& corners = set.mesh->triangles()[location.triangle];
  for (int corner = 0; corner < 3; ++corner) {
    const int32_t held = set.sample_of(corners[corner]);
    if (held < 0) continue;
    const uint32_t sample = static_cast<uint32_t>(held);
    if (blend == Blend::aligned) {
      const glm::mat3 rotation = rotation_between(direction, set.directions[sample]);
      add_read(reads, sample, location.weights[corner], rotation, true);
    } else {
      add_read(reads, sample, location.weights[corner], glm::mat3(1.0f), false);
    }
  }
  return reads;
}

}  // namespace causticbench::lpi
