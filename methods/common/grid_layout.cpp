#include "methods/common/grid_layout.h"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace causticbench {

bool clip_to_ball(const PathSegment& segment, const Vec3& center, float radius, float& t_enter, float& t_exit) {
  const Vec3 offset = segment.origin - center;
  const float half_b = glm::dot(offset, segment.direction);
  const float c = glm::dot(offset, offset) - radius * radius;
  const float discriminant = half_b * half_b - c;
  if (!(discriminant > 0.0f)) return false;
  const float root = std::sqrt(discriminant);
  t_enter = std::max(0.0f, -half_b - root);
  t_exit = std::min(segment.length, -half_b + root);
  return t_exit > t_enter;
}

GridLayout::GridLayout(Vec3 center, float radius, int resolution)
    : VolumeLayout(center, radius), resolution_(resolution) {
  if (resolution < 1) throw std::invalid_argument("GridLayout: resolution below 1");
  cell_ = 2.0f * radius / static_cast<float>(resolution);
  minimum_ = center - Vec3(radius);
  for (int axis = 0; axis < 3; ++axis) {
    axis_offsets_[axis].resize(static_cast<size_t>(resolution));
    for (int i = 0; i < resolution; ++i) {
      axis_offsets_[axis][static_cast<size_t>(i)] =
          (minimum_[axis] + cell_ * (static_cast<float>(i) + 0.5f)) - center[axis];
    }
  }
}

Vec3 GridLayout::cell_center(int x, int y, int z) const {
  return minimum_ + cell_ * (Vec3(static_cast<float>(x), static_cast<float>(y), static_cast<float>(z)) + 0.5f);
}

// Amanatides & Woo's traversal: cell after cell along the segment, each with the exact length of
// track inside it, so that a uniform beam gives every cell exactly its irradiance.
void GridLayout::deposit(const PathSegment& segment, Orientation orientation, float* sums) const {
  const int channels = channel_count(orientation);
  // The cell's offset from the centre, axis by axis from the table: what cell_center(...) - center_
  // gives, bit for bit, without its multiplications.
  const float* offsets[3] = {axis_offsets_[0].data(), axis_offsets_[1].data(), axis_offsets_[2].data()};
  const bool paper = orientation == Orientation::paper;
  walk(segment, [&](size_t cell_index, const int* cell, float length) {
    float* cell_sums = sums + cell_index * static_cast<size_t>(channels);
    if (paper) {
      const Vec3 to_cell(offsets[0][cell[0]], offsets[1][cell[1]], offsets[2][cell[2]]);
      // A cell the track travels towards the centre in gets cos 0: skipped before the square root
      // and divisions when the sign is certain (the margin covers both dot products' rounding;
      // |direction| components are at most 1), so what is added is unchanged.
      const float towards = glm::dot(segment.direction, to_cell);
      const float margin = 1e-5f * (std::fabs(to_cell.x) + std::fabs(to_cell.y) + std::fabs(to_cell.z));
      if (towards >= -margin) {
        const float distance = glm::length(to_cell);
        const Vec3 sample_direction = distance > 0.0f ? to_cell / distance : Vec3(0.0f);
        add_track(segment, length, sample_direction, orientation, cell_sums);
      }
    } else {
      // The vector orientation does not use the sample's direction.
      add_track(segment, length, Vec3(0.0f), orientation, cell_sums);
    }
  });
}

void GridLayout::normalise(double photons_emitted, Orientation orientation, double* values) const {
  const double factor = 1.0 / (static_cast<double>(cell_) * cell_ * cell_ * photons_emitted);
  const size_t count = points() * static_cast<size_t>(channel_count(orientation));
  for (size_t i = 0; i < count; ++i) values[i] *= factor;
}

}  // namespace causticbench
