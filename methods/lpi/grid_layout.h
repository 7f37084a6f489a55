// `storage: grid` (Wyman 2003, Section 4.2): a uniform grid of resolution^3 cubic cells over the
// cube that bounds the sampled ball. Each cell holds the mean irradiance over the cell (the
// track-length estimator, with exact segment-cell lengths from a 3D DDA), read back by trilinear
// interpolation between cell centres (clamped to the outermost centres).
#pragma once

#include <algorithm>

#include "methods/lpi/volume_layout.h"

namespace causticbench::lpi {

class GridLayout final : public VolumeLayout {
 public:
  GridLayout(Vec3 center, float radius, int resolution);
  size_t points() const override { return static_cast<size_t>(resolution_) * resolution_ * resolution_; }
  // Pieces of track inside the cube (not only the ball) count: the cells at the ball's edge reach
  // beyond it, and their means must be of the whole cell.
  void deposit(const PathSegment& segment, Orientation orientation, float* sums) const override;
  void normalise(double photons_emitted, Orientation orientation, double* values) const override;
  Stencil stencil(const Vec3& position) const override;
  size_t memory_bytes() const override { return 0; }

  int resolution() const { return resolution_; }
  float cell_size() const { return cell_; }
  Vec3 cell_center(int x, int y, int z) const;
  size_t index(int x, int y, int z) const { return (static_cast<size_t>(z) * resolution_ + y) * resolution_ + x; }

 private:
  int resolution_;
  float cell_;
  Vec3 minimum_;  // corner of the cube
};

// In the header, so that it inlines into lpi's per-pixel lookup (methods/lpi/lookup.h): out of line it
// took a quarter of a barycentric frame's time in calls.
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
