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
  const Vec3 maximum = minimum_ + Vec3(2.0f * radius_);
  float t_enter = 0.0f, t_exit = segment.length;
  for (int axis = 0; axis < 3; ++axis) {
    const float d = segment.direction[axis], o = segment.origin[axis];
    if (d == 0.0f) {
      if (o < minimum_[axis] || o >= maximum[axis]) return;
      continue;
    }
    float t0 = (minimum_[axis] - o) / d, t1 = (maximum[axis] - o) / d;
    if (t0 > t1) std::swap(t0, t1);
    t_enter = std::max(t_enter, t0);
    t_exit = std::min(t_exit, t1);
  }
  if (!(t_exit > t_enter)) return;
  int cell[3], step[3];
  float t_next[3], t_delta[3];
  const Vec3 start = segment.origin + segment.direction * t_enter;
  for (int axis = 0; axis < 3; ++axis) {
    const float d = segment.direction[axis];
    const float local = (start[axis] - minimum_[axis]) / cell_;
    cell[axis] = std::clamp(static_cast<int>(std::floor(local)), 0, resolution_ - 1);
    if (d > 0.0f) {
      step[axis] = 1;
      t_delta[axis] = cell_ / d;
      t_next[axis] = (minimum_[axis] + (cell[axis] + 1) * cell_ - segment.origin[axis]) / d;
    } else if (d < 0.0f) {
      step[axis] = -1;
      t_delta[axis] = -cell_ / d;
      t_next[axis] = (minimum_[axis] + cell[axis] * cell_ - segment.origin[axis]) / d;
    } else {
      step[axis] = 0;
      t_delta[axis] = std::numeric_limits<float>::infinity();
      t_next[axis] = std::numeric_limits<float>::infinity();
    }
  }
  // The cell's offset from the centre, axis by axis from the table: what cell_center(...) - center_
  // gives, bit for bit, without its multiplications.
  const float* offsets[3] = {axis_offsets_[0].data(), axis_offsets_[1].data(), axis_offsets_[2].data()};
  const size_t row = static_cast<size_t>(resolution_), slice = row * row;
  const ptrdiff_t index_step[3] = {step[0], step[1] * static_cast<ptrdiff_t>(row), step[2] * static_cast<ptrdiff_t>(slice)};
  float* cell_sums = sums + index(cell[0], cell[1], cell[2]) * static_cast<size_t>(channels);
  const bool paper = orientation == Orientation::paper;
  float t = t_enter;
  while (t < t_exit) {
    int axis = t_next[0] < t_next[1] ? (t_next[0] < t_next[2] ? 0 : 2) : (t_next[1] < t_next[2] ? 1 : 2);
    const float t_end = std::min(t_next[axis], t_exit);
    if (t_end > t) {
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
          add_track(segment, t_end - t, sample_direction, orientation, cell_sums);
        }
      } else {
        // The vector orientation does not use the sample's direction.
        add_track(segment, t_end - t, Vec3(0.0f), orientation, cell_sums);
      }
    }
    t = t_end;
    if (t >= t_exit) break;
    cell[axis] += step[axis];
    if (cell[axis] < 0 || cell[axis] >= resolution_) break;
    cell_sums += index_step[axis] * channels;
    t_next[axis] += t_delta[axis];
  }
}

void GridLayout::normalise(double photons_emitted, Orientation orientation, double* values) const {
  const double factor = 1.0 / (static_cast<double>(cell_) * cell_ * cell_ * photons_emitted);
  const size_t count = points() * static_cast<size_t>(channel_count(orientation));
  for (size_t i = 0; i < count; ++i) values[i] *= factor;
}

}  // namespace causticbench
