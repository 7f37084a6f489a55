// `storage: multires` (Wyman 2003, Section 4.3: "storing densely sampled data only where
// necessary"): an octree over the cube of the grid, refined only where the caustic varies.
//
// Built from the finest level down, so that every stored value stays a track-length estimate: the
// photons are deposited into the finest grid (2^depth cells a side, exactly as `storage: grid`),
// then a subtree is collapsed into one leaf holding the volume mean of its finest cells (the
// track-length estimate over the larger cell, no less unbiased) whenever every finest cell in it,
// for every light sample the tree serves and every channel, lies within error_threshold x (that
// light sample's largest value) of the mean. Two kinds of tree (`multires_tree`): one shared by all light samples (a cell
// is refined if any light sample's caustic varies in it), or one per light sample (each refined only
// where its own caustic varies; the sample's values are the leaves of its own tree, so the light
// samples' blocks differ in size).
//
// Lookup: trilinear interpolation between the centres of the finest cells, as on the finest grid,
// each centre taking the value of the leaf that contains it. The reconstruction is continuous
// everywhere, and since the weights are convex it differs from the finest grid's lookup by at most
// error_threshold x the light sample's largest value (error_threshold 0 reads exactly as the grid).
// With a tree per light sample the eight finest centres are the same for every sample; only the
// leaves they fall in differ, so a lookup makes the finest stencil once and maps it through each
// read sample's tree.
#pragma once

#include <vector>

#include "methods/common/grid_layout.h"

namespace causticbench::lpi {

enum class MultiresTree { shared, per_sample };

class MultiresLayout final : public VolumeLayout {
 public:
  MultiresLayout(Vec3 center, float radius, int depth, double error_threshold,
                 MultiresTree trees = MultiresTree::shared);
  // Leaves of the tree (one before adapt(): the root); per light sample, of all its trees together.
  size_t points() const override { return leaves_; }
  // Per light sample the leaves of its own tree; shared: every block has points().
  std::vector<size_t> block_points(size_t blocks) const override;
  size_t deposit_points() const override { return finest_.points(); }
  bool adaptive() const override { return true; }
  void deposit(const PathSegment& segment, Orientation orientation, float* sums) const override {
    finest_.deposit(segment, orientation, sums);
  }
  void normalise(double photons_emitted, Orientation orientation, double* values) const override {
    finest_.normalise(photons_emitted, orientation, values);
  }
  std::vector<float> adapt(const std::vector<float>& finest_values, int channels) override;
  // The shared tree's stencil; with a tree per light sample there is none common to the samples
  // (std::logic_error): read through finest_stencil() and to_leaves() instead.
  Stencil stencil(const Vec3& position) const override;
  size_t memory_bytes() const override { return 0; }
  // The node words, and per light sample one word for its tree's root.
  size_t index_bytes() const override { return (nodes_.size() + roots_.size()) * sizeof(uint32_t); }
  std::vector<uint32_t> structure() const override;
  void restore(std::vector<uint32_t> structure) override;

  int depth() const { return depth_; }
  const GridLayout& finest() const { return finest_; }
  bool per_sample() const { return trees_ == MultiresTree::per_sample; }
  size_t nodes() const { return nodes_.size(); }
  // Trees: one per light sample, or the shared one.
  size_t sample_trees() const { return per_sample() ? roots_.size() : 1; }
  // Node words of the tree that serves `sample` (shared: the one tree's).
  size_t sample_nodes(size_t sample) const;
  // The leaf (value index within its light sample's block) holding finest cell (x, y, z), in the
  // tree of `sample` (the shared tree for any sample).
  uint32_t leaf_of(int x, int y, int z, size_t sample = 0) const;
  // The finest grid's stencil at `position`, and its finest cells turned into the leaves of the tree
  // of `sample`.
  Stencil finest_stencil(const Vec3& position) const { return finest_.stencil(position); }
  void to_leaves(Stencil& stencil, size_t sample) const;

 private:
  // Node word: the leaf flag in the top bit and a value index below it, or the index of the first of
  // eight consecutive children (x fastest, then y, then z).
  static constexpr uint32_t kLeaf = 0x80000000u;

  // Appends the tree over the light samples [first, first + count) of `finest_values` to nodes_, its
  // leaves' means (light samples x channels each, in leaf order) to `leaf_means`.
  void build_tree(const std::vector<float>& finest_values, int channels, size_t first, size_t count,
                  const std::vector<double>& tolerance, std::vector<std::vector<double>>& leaf_means);
  uint32_t root_of(size_t sample) const { return roots_.empty() ? 0u : roots_[sample]; }

  int depth_;
  double error_threshold_;
  MultiresTree trees_;
  GridLayout finest_;
  // Every tree's nodes; per light sample the trees follow each other, tree s from roots_[s].
  std::vector<uint32_t> nodes_{kLeaf};
  std::vector<uint32_t> roots_;   // per light sample (empty when shared)
  std::vector<size_t> sample_leaves_;  // per light sample (empty when shared)
  size_t leaves_ = 1;
};

}  // namespace causticbench::lpi
