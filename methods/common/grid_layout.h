// `storage: grid` (Wyman 2003, Section 4.2): a uniform grid of resolution^3 cubic cells over the
// cube that bounds the sampled ball. Each cell holds the mean irradiance over the cell (the
// track-length estimator, with exact segment-cell lengths from a 3D DDA), read back by trilinear
// interpolation between cell centres (clamped to the outermost centres).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

#include "methods/common/volume_layout.h"

namespace causticbench {

class GridLayout final : public VolumeLayout {
 public:
  GridLayout(Vec3 center, float radius, int resolution);
  size_t points() const override { return static_cast<size_t>(resolution_) * resolution_ * resolution_; }
  // Pieces of track inside the cube (not only the ball) count: the cells at the ball's edge reach
  // beyond it, and their means must be of the whole cell.
  void deposit(const PathSegment& segment, Orientation orientation, float* sums) const override;
  void normalise(double photons_emitted, Orientation orientation, double* values) const override;
  // Inline: the lookup's per-point work (lookup.h) calls it through the concrete type.
  Stencil stencil(const Vec3& position) const override;
  size_t memory_bytes() const override { return 0; }

  // Calls visit(cell index, cell coordinates (3 ints), length) for each cell the segment crosses inside
  // the cube, in order along it (a 3D DDA), with the exact length of segment inside the cell.
  template <class Visit>
  void walk(const PathSegment& segment, Visit&& visit) const;

  int resolution() const { return resolution_; }
  float cell_size() const { return cell_; }
  Vec3 cell_center(int x, int y, int z) const;
  size_t index(int x, int y, int z) const { return (static_cast<size_t>(z) * resolution_ + y) * resolution_ + x; }

 private:
  int resolution_;
  float cell_;
  Vec3 minimum_;  // corner of the cube
  // Per axis, cell i's centre minus the ball's centre: the paper orientation's sample direction
  // along a track, looked up rather than recomputed at every cell the DDA visits.
  std::array<std::vector<float>, 3> axis_offsets_;
};

template <class Visit>
void GridLayout::walk(const PathSegment& segment, Visit&& visit) const {
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
  const size_t row = static_cast<size_t>(resolution_), slice = row * row;
  const ptrdiff_t index_step[3] = {step[0], step[1] * static_cast<ptrdiff_t>(row), step[2] * static_cast<ptrdiff_t>(slice)};
  size_t cell_index = index(cell[0], cell[1], cell[2]);
  float t = t_enter;
  while (t < t_exit) {
    int axis = t_next[0] < t_next[1] ? (t_next[0] < t_next[2] ? 0 : 2) : (t_next[1] < t_next[2] ? 1 : 2);
    const float t_end = std::min(t_next[axis], t_exit);
    if (t_end > t) visit(cell_index, static_cast<const int*>(cell), t_end - t);
    t = t_end;
    if (t >= t_exit) break;
    cell[axis] += step[axis];
    if (cell[axis] < 0 || cell[axis] >= resolution_) break;
    cell_index = static_cast<size_t>(static_cast<ptrdiff_t>(cell_index) + index_step[axis]);
    t_next[axis] += t_delta[axis];
  }
}

inline Stencil GridLayout::stencil(const Vec3& position) const {
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
  const uint32_t first = static_cast<uint32_t>(index(base[0], base[1], base[2]));
  if (resolution_ == 1) {
    stencil.count = 1;
    stencil.points[0] = first;
    stencil.weights[0] = (1.0f - fraction[0]) * (1.0f - fraction[1]) * (1.0f - fraction[2]);
    return stencil;
  }
  // Corner (dx, dy, dz) = bits of its number, x lowest; its weight is the product in x, y, z order.
  const float x[2] = {1.0f - fraction[0], fraction[0]}, y[2] = {1.0f - fraction[1], fraction[1]},
              z[2] = {1.0f - fraction[2], fraction[2]};
  const uint32_t row = static_cast<uint32_t>(resolution_), slice = row * row;
  const float xy[4] = {x[0] * y[0], x[1] * y[0], x[0] * y[1], x[1] * y[1]};
  const uint32_t offsets[4] = {0, 1, row, row + 1};
  for (int corner = 0; corner < 4; ++corner) {
    stencil.points[corner] = first + offsets[corner];
    stencil.weights[corner] = xy[corner] * z[0];
    stencil.points[corner + 4] = first + slice + offsets[corner];
    stencil.weights[corner + 4] = xy[corner] * z[1];
  }
  stencil.count = 8;
  return stencil;
}

}  // namespace causticbench
