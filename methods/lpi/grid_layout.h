// `storage: grid` (Wyman 2003, Section 4.2): a uniform grid of resolution^3 cubic cells over the
// cube that bounds the sampled ball. Each cell holds the mean irradiance over the cell (the
// track-length estimator, with exact segment-cell lengths from a 3D DDA), read back by trilinear
// interpolation between cell centres (clamped to the outermost centres).
#pragma once

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

}  // namespace causticbench::lpi
