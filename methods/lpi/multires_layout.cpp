#include "methods/lpi/multires_layout.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <stdexcept>

#include <fmt/format.h>

namespace causticbench::lpi {

MultiresLayout::MultiresLayout(Vec3 center, float radius, int depth, double error_threshold, MultiresTree trees)
    : VolumeLayout(center, radius), depth_(depth), error_threshold_(error_threshold), trees_(trees),
      finest_(center, radius, 1 << depth) {
  if (depth < 0 || depth > 9) throw std::invalid_argument(fmt::format("MultiresLayout: depth {} outside 0 .. 9", depth));
  if (!(error_threshold >= 0.0)) throw std::invalid_argument("MultiresLayout: negative error threshold");
}

namespace {

struct Region {
  uint32_t node;
  int x, y, z, size;
};

}  // namespace

// Breadth first, so that the eight children of a node are consecutive and the leaves are numbered
// in a fixed order: the same tree and values for any thread count.
void MultiresLayout::build_tree(const std::vector<float>& finest_values, int channels, size_t first, size_t count,
                                const std::vector<double>& tolerance, std::vector<std::vector<double>>& leaf_means) {
  const size_t block = finest_.points() * static_cast<size_t>(channels);
  auto value = [&](size_t s, int x, int y, int z, int c) {
    return finest_values[s * block + finest_.index(x, y, z) * channels + c];
  };
  std::vector<double> means(count * channels);
  // Means of every light sample and channel over the region; whether every finest cell lies within
  // the tolerance of them. Cell counts are powers of two, so a region of equal values has exactly
  // that mean and collapses even at threshold 0.
  auto collapses = [&](const Region& region) {
    const double cells = static_cast<double>(region.size) * region.size * region.size;
    for (size_t s = 0; s < count; ++s) {
      for (int c = 0; c < channels; ++c) {
        double sum = 0.0;
        for (int z = region.z; z < region.z + region.size; ++z)
          for (int y = region.y; y < region.y + region.size; ++y)
            for (int x = region.x; x < region.x + region.size; ++x) sum += value(first + s, x, y, z, c);
        means[s * channels + c] = sum / cells;
      }
    }
    if (region.size == 1) return true;
    for (size_t s = 0; s < count; ++s) {
      for (int c = 0; c < channels; ++c) {
        const double mean = means[s * channels + c];
        for (int z = region.z; z < region.z + region.size; ++z)
          for (int y = region.y; y < region.y + region.size; ++y)
            for (int x = region.x; x < region.x + region.size; ++x) {
              if (std::fabs(value(first + s, x, y, z, c) - mean) > tolerance[first + s]) return false;
            }
      }
    }
    return true;
  };
  const size_t first_leaf = leaf_means.size();
  const uint32_t root = static_cast<uint32_t>(nodes_.size());
  nodes_.push_back(0u);
  std::deque<Region> queue{{root, 0, 0, 0, finest_.resolution()}};
  while (!queue.empty()) {
    const Region region = queue.front();
    queue.pop_front();
    if (collapses(region)) {
      // Leaf indices count within the tree: they index its light samples' blocks.
      nodes_[region.node] = kLeaf | static_cast<uint32_t>(leaf_means.size() - first_leaf);
      leaf_means.push_back(means);
      continue;
    }
    const uint32_t children = static_cast<uint32_t>(nodes_.size());
    if (children + 8 >= kLeaf) throw std::runtime_error("MultiresLayout: more than 2^31 nodes");
    nodes_[region.node] = children;
    nodes_.resize(nodes_.size() + 8, 0u);
    const int half = region.size / 2;
    for (int child = 0; child < 8; ++child) {
      queue.push_back({children + static_cast<uint32_t>(child), region.x + (child & 1) * half,
                       region.y + ((child >> 1) & 1) * half, region.z + ((child >> 2) & 1) * half, half});
    }
  }
}

std::vector<float> MultiresLayout::adapt(const std::vector<float>& finest_values, int channels) {
  const size_t block = finest_.points() * static_cast<size_t>(channels);
  if (block == 0 || finest_values.size() % block != 0) {
    throw std::logic_error(fmt::format("MultiresLayout::adapt: {} values are not whole blocks of {}", finest_values.size(), block));
  }
  const size_t samples = finest_values.size() / block;
  // Per light sample, the largest magnitude: the threshold is relative to it, as uint8's steps are.
  std::vector<double> tolerance(samples, 0.0);
  for (size_t s = 0; s < samples; ++s) {
    float largest = 0.0f;
    for (size_t i = 0; i < block; ++i) largest = std::max(largest, std::fabs(finest_values[s * block + i]));
    tolerance[s] = error_threshold_ * largest;
  }
  nodes_.clear();
  roots_.clear();
  sample_leaves_.clear();
  std::vector<float> values;
  if (trees_ == MultiresTree::shared) {
    std::vector<std::vector<double>> leaf_means;  // per leaf: samples x channels
    build_tree(finest_values, channels, 0, samples, tolerance, leaf_means);
    leaves_ = leaf_means.size();
    values.resize(samples * leaves_ * channels);
    for (size_t s = 0; s < samples; ++s)
      for (size_t leaf = 0; leaf < leaves_; ++leaf)
        for (int c = 0; c < channels; ++c)
          values[(s * leaves_ + leaf) * channels + c] = static_cast<float>(leaf_means[leaf][s * channels + c]);
    return values;
  }
  // A tree per light sample, one after the other; each sample's block is its own tree's leaves.
  leaves_ = 0;
  for (size_t s = 0; s < samples; ++s) {
    std::vector<std::vector<double>> leaf_means;  // per leaf: channels
    roots_.push_back(static_cast<uint32_t>(nodes_.size()));
    build_tree(finest_values, channels, s, 1, tolerance, leaf_means);
    sample_leaves_.push_back(leaf_means.size());
    leaves_ += leaf_means.size();
    for (const std::vector<double>& means : leaf_means)
      for (int c = 0; c < channels; ++c) values.push_back(static_cast<float>(means[c]));
  }
  return values;
}

std::vector<size_t> MultiresLayout::block_points(size_t blocks) const {
  if (trees_ == MultiresTree::shared) return std::vector<size_t>(blocks, leaves_);
  if (blocks != sample_leaves_.size()) {
    throw std::logic_error(fmt::format("MultiresLayout: {} blocks for {} light samples' trees", blocks, sample_leaves_.size()));
  }
  return sample_leaves_;
}

size_t MultiresLayout::sample_nodes(size_t sample) const {
  if (trees_ == MultiresTree::shared) return nodes_.size();
  const size_t end = sample + 1 < roots_.size() ? roots_[sample + 1] : nodes_.size();
  return end - roots_[sample];
}

// Shared: the node words. Per light sample: the count of trees, each tree's root, then the node words.
std::vector<uint32_t> MultiresLayout::structure() const {
  if (trees_ == MultiresTree::shared) return nodes_;
  std::vector<uint32_t> words{static_cast<uint32_t>(roots_.size())};
  words.insert(words.end(), roots_.begin(), roots_.end());
  words.insert(words.end(), nodes_.begin(), nodes_.end());
  return words;
}

void MultiresLayout::restore(std::vector<uint32_t> structure) {
  std::vector<uint32_t> roots;
  if (trees_ == MultiresTree::per_sample) {
    if (structure.empty() || structure[0] == 0 || structure[0] >= structure.size()) {
      throw std::runtime_error("multires trees: no light sample's tree");
    }
    const size_t trees = structure[0];
    roots.assign(structure.begin() + 1, structure.begin() + 1 + static_cast<std::ptrdiff_t>(trees));
    structure.erase(structure.begin(), structure.begin() + 1 + static_cast<std::ptrdiff_t>(trees));
  } else {
    roots = {0u};
  }
  if (structure.empty() || roots.front() != 0u) throw std::runtime_error("multires tree: no root");
  // Each tree lies in [its root, the next root): its children after their parent, inside it.
  std::vector<size_t> sample_leaves;
  for (size_t t = 0; t < roots.size(); ++t) {
    const size_t begin = roots[t], end = t + 1 < roots.size() ? roots[t + 1] : structure.size();
    if (end <= begin || end > structure.size()) throw std::runtime_error("multires trees: roots out of order");
    size_t leaves = 0;
    for (size_t i = begin; i < end; ++i) {
      const uint32_t word = structure[i];
      if (word & kLeaf) {
        ++leaves;
      } else if (word <= i || static_cast<size_t>(word) + 8 > end) {
        throw std::runtime_error("multires tree: a child index out of order");
      }
    }
    sample_leaves.push_back(leaves);
  }
  nodes_ = std::move(structure);
  leaves_ = 0;
  for (size_t leaves : sample_leaves) leaves_ += leaves;
  if (trees_ == MultiresTree::per_sample) {
    roots_ = std::move(roots);
    sample_leaves_ = std::move(sample_leaves);
  }
}

uint32_t MultiresLayout::leaf_of(int x, int y, int z, size_t sample) const {
  uint32_t word = nodes_[root_of(sample)];
  for (int level = depth_ - 1; !(word & kLeaf); --level) {
    const uint32_t child = static_cast<uint32_t>(((x >> level) & 1) | (((y >> level) & 1) << 1) | (((z >> level) & 1) << 2));
    word = nodes_[word + child];
  }
  return word & ~kLeaf;
}

void MultiresLayout::to_leaves(Stencil& stencil, size_t sample) const {
  const int resolution = finest_.resolution();
  for (int s = 0; s < stencil.count; ++s) {
    const uint32_t cell = stencil.points[s];
    const int x = static_cast<int>(cell % resolution), y = static_cast<int>((cell / resolution) % resolution),
              z = static_cast<int>(cell / (static_cast<uint32_t>(resolution) * resolution));
    stencil.points[s] = leaf_of(x, y, z, sample);
  }
}

Stencil MultiresLayout::stencil(const Vec3& position) const {
  if (trees_ == MultiresTree::per_sample) {
    throw std::logic_error("MultiresLayout::stencil: a tree per light sample has no stencil common to the samples");
  }
  Stencil stencil = finest_.stencil(position);
  to_leaves(stencil, 0);
  return stencil;
}

}  // namespace causticbench::lpi
