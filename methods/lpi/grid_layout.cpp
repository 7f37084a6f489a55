#include "methods/lpi/grid_layout.h"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace causticbench::lpi {

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
  float t = t_enter;
  while (t < t_exit) {
    int axis = t_next[0] < t_next[1] ? (t_next[0] < t_next[2] ? 0 : 2) : (t_next[1] < t_next[2] ? 1 : 2);
    const float t_end = std::min(t_next[axis], t_exit);
    if (t_end > t) {
      const Vec3 to_cell = cell_center(cell[0], cell[1], cell[2]) - center_;
      const float distance = glm::length(to_cell);
      const Vec3 sample_direction = distance > 0.0f ? to_cell / distance : Vec3(0.0f);
      add_track(segment, t_end - t, sample_direction, orientation,
                sums + index(cell[0], cell[1], cell[2]) * static_cast<size_t>(channels));
    }
    t = t_end;
    if (t >= t_exit) break;
    cell[axis] += step[axis];
    if (cell[axis] < 0 || cell[axis] >= resolution_) break;
    t_next[axis] += t_delta[axis];
  }
}

void GridLayout::normalise(double photons_emitted, Orientation orientation, double* values) const {
  const double factor = 1.0 / (static_cast<double>(cell_) * cell_ * cell_ * photons_emitted);
  const size_t count = points() * static_cast<size_t>(channel_count(orientation));
  for (size_t i = 0; i < count; ++i) values[i] *= factor;
}

Stencil GridLayout::stencil(const Vec3& position) const {
  Stencil stencil;
  int base[3];
  float fraction[3];
  for (int axis = 0; axis < 3; ++axis) {
    // Cell centres sit at half-integer coordinates; beyond the outermost ones the value is held.
    float local = (position[axis] - minimum_[axis]) / cell_ - 0.5f;
    local = std::clamp(local, 0.0f, static_cast<float>(resolution_ - 1));
    base[axis] = std::min(static_cast<int>(local), std::max(0, resolution_ - 2));
    fraction[axis] = resolution_ > 1 ? local - static_cast<float>(base[axis]) : 0.0f;
  }
  const int upper = resolution_ > 1 ? 1 : 0;
  for (int corner = 0; corner < 8; ++corner) {
    const int dx = corner & 1, dy = (corner >> 1) & 1, dz = (corner >> 2) & 1;
    if ((dx || dy || dz) && !upper) continue;
    const float weight = (dx ? fraction[0] : 1.0f - fraction[0]) * (dy ? fraction[1] : 1.0f - fraction[1]) *
                         (dz ? fraction[2] : 1.0f - fraction[2]);
    stencil.points[stencil.count] = static_cast<uint32_t>(index(base[0] + dx, base[1] + dy, base[2] + dz));
    stencil.weights[stencil.count] = weight;
    ++stencil.count;
  }
  return stencil;
}

}  // namespace causticbench::lpi
