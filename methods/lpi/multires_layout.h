// `storage: multires` (Wyman 2003, Section 4.3: "storing densely sampled data only where
// necessary"): an octree over the cube of the grid, refined only where the caustic varies.
//
// Built from the finest level down, so that every stored value stays a track-length estimate: the
// photons are deposited into the finest grid (2^depth cells a side, exactly as `storage: grid`),
// then a subtree is collapsed into one leaf holding the volume mean of its finest cells (the
// track-length estimate over the larger cell, no less unbiased) whenever every finest cell in it,
// for every light sample and channel, lies within error_threshold x (that light sample's largest
// value) of the mean. The tree is shared by all light samples: a cell is refined if any light
// sample's caustic varies in it.
//
// Lookup: trilinear interpolation between the centres of the finest cells, as on the finest grid,
// each centre taking the value of the leaf that contains it. The reconstruction is continuous
// everywhere, and since the weights are convex it differs from the finest grid's lookup by at most
// error_threshold x the light sample's largest value (error_threshold 0 reads exactly as the grid).
#pragma once

#include <vector>

#include "methods/lpi/grid_layout.h"

namespace causticbench::lpi {

class MultiresLayout final : public VolumeLayout {
 public:
  MultiresLayout(Vec3 center, float radius, int depth, double error_threshold);
  // Leaves of the tree (one before adapt(): the root).
  size_t points() const override { return leaves_; }
  size_t deposit_points() const override { return finest_.points(); }
  bool adaptive() const override { return true; }
  void deposit(const PathSegment& segment, Orientation orientation, float* sums) const override {
    finest_.deposit(segment, orientation, sums);
  }
  void normalise(double photons_emitted, Orientation orientation, double* values) const override {
    finest_.normalise(photons_emitted, orientation, values);
  }
  std::vector<float> adapt(const std::vector<float>& finest_values, int channels) override;
  Stencil stencil(const Vec3& position) const override;
  size_t memory_bytes() const override { return 0; }
  size_t index_bytes() const override { return nodes_.size() * sizeof(uint32_t); }
  std::vector<uint32_t> structure() const override { return nodes_; }
  void restore(std::vector<uint32_t> structure) override;

  int depth() const { return depth_; }
  const GridLayout& finest() const { return finest_; }
  size_t nodes() const { return nodes_.size(); }
  // The leaf (value index) holding finest cell (x, y, z).
  uint32_t leaf_of(int x, int y, int z) const;

 private:
  // Node word: the leaf flag in the top bit and a value index below it, or the index of the first of
  // eight consecutive children (x fastest, then y, then z).
  static constexpr uint32_t kLeaf = 0x80000000u;

  int depth_;
  double error_threshold_;
  GridLayout finest_;
  std::vector<uint32_t> nodes_{kLeaf};
  size_t leaves_ = 1;
};

}  // namespace causticbench::lpi
