#include "methods/lpi/multires_layout.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <stdexcept>

#include <fmt/format.h>

namespace causticbench::lpi {

MultiresLayout::MultiresLayout(Vec3 center, float radius, int depth, double error_threshold)
    : VolumeLayout(center, radius), depth_(depth), error_threshold_(error_threshold), finest_(center, radius, 1 << depth) {
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
std::vector<float> MultiresLayout::adapt(const std::vector<float>& finest_values, int channels) {
  const int resolution = finest_.resolution();
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
  auto value = [&](size_t s, int x, int y, int z, int c) {
    return finest_values[s * block + finest_.index(x, y, z) * channels + c];
  };
  std::vector<std::vector<double>> leaf_means;  // per leaf: samples x channels
  std::vector<double> means(samples * channels);
  // Means of every light sample and channel over the region; whether every finest cell lies within
  // the tolerance of them. Cell counts are powers of two, so a region of equal values has exactly
  // that mean and collapses even at threshold 0.
  auto collapses = [&](const Region& region) {
    const double cells = static_cast<double>(region.size) * region.size * region.size;
    for (size_t s = 0; s < samples; ++s) {
      for (int c = 0; c < channels; ++c) {
        double sum = 0.0;
        for (int z = region.z; z < region.z + region.size; ++z)
          for (int y = region.y; y < region.y + region.size; ++y)
            for (int x = region.x; x < region.x + region.size; ++x) sum += value(s, x, y, z, c);
        means[s * channels + c] = sum / cells;
      }
    }
    if (region.size == 1) return true;
    for (size_t s = 0; s < samples; ++s) {
      for (int c = 0; c < channels; ++c) {
        const double mean = means[s * channels + c];
        for (int z = region.z; z < region.z + region.size; ++z)
          for (int y = region.y; y < region.y + region.size; ++y)
            for (int x = region.x; x < region.x + region.size; ++x) {
              if (std::fabs(value(s, x, y, z, c) - mean) > tolerance[s]) return false;
            }
      }
    }
    return true;
  };
  nodes_.assign(1, 0u);
  std::deque<Region> queue{{0u, 0, 0, 0, resolution}};
  while (!queue.empty()) {
    const Region region = queue.front();
    queue.pop_front();
    if (collapses(region)) {
      nodes_[region.node] = kLeaf | static_cast<uint32_t>(leaf_means.size());
      leaf_means.push_back(means);
      continue;
    }
    const uint32_t first = static_cast<uint32_t>(nodes_.size());
    if (first + 8 >= kLeaf) throw std::runtime_error("MultiresLayout: more than 2^31 nodes");
    nodes_[region.node] = first;
    nodes_.resize(nodes_.size() + 8, 0u);
    const int half = region.size / 2;
    for (int child = 0; child < 8; ++child) {
      queue.push_back({first + static_cast<uint32_t>(child), region.x + (child & 1) * half,
                       region.y + ((child >> 1) & 1) * half, region.z + ((child >> 2) & 1) * half, half});
    }
  }
  leaves_ = leaf_means.size();
  std::vector<float> values(samples * leaves_ * channels);
  for (size_t s = 0; s < samples; ++s) {
    for (size_t leaf = 0; leaf < leaves_; ++leaf) {
      for (int c = 0; c < channels; ++c) {
        values[(s * leaves_ + leaf) * channels + c] = static_cast<float>(leaf_means[leaf][s * channels + c]);
      }
    }
  }
  return values;
}

void MultiresLayout::restore(std::vector<uint32_t> structure) {
  size_t leaves = 0;
  for (size_t i = 0; i < structure.size(); ++i) {
    const uint32_t word = structure[i];
    if (word & kLeaf) {
      ++leaves;
    } else if (word <= i || static_cast<size_t>(word) + 8 > structure.size()) {
      throw std::runtime_error("multires tree: a child index out of order");
    }
  }
  if (structure.empty()) throw std::runtime_error("multires tree: no root");
  nodes_ = std::move(structure);
  leaves_ = leaves;
}

uint32_t MultiresLayout::leaf_of(int x, int y, int z) const {
  uint32_t word = nodes_[0];
  for (int level = depth_ - 1; !(word & kLeaf); --level) {
    const uint32_t child = static_cast<uint32_t>(((x >> level) & 1) | (((y >> level) & 1) << 1) | (((z >> level) & 1) << 2));
    word = nodes_[word + child];
  }
  return word & ~kLeaf;
}

Stencil MultiresLayout::stencil(const Vec3& position) const {
  Stencil stencil = finest_.stencil(position);
  const int resolution = finest_.resolution();
  for (int s = 0; s < stencil.count; ++s) {
    const uint32_t cell = stencil.points[s];
    const int x = static_cast<int>(cell % resolution), y = static_cast<int>((cell / resolution) % resolution),
              z = static_cast<int>(cell / (static_cast<uint32_t>(resolution) * resolution));
    stencil.points[s] = leaf_of(x, y, z);
  }
  return stencil;
}

}  // namespace causticbench::lpi
