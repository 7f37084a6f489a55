#include "methods/common/photon_grid.h"

namespace causticbench {

PhotonGrid::PhotonGrid(const std::vector<Photon>& photons, float cell_size)
    : photons_(photons), inverse_cell_(1.0f / cell_size) {
  uint32_t table_size = 1;
  while (table_size < 2 * photons.size() + 1) table_size <<= 1;
  mask_ = table_size - 1;
  starts_.assign(table_size + 1, 0);
  std::vector<uint32_t> buckets(photons.size());
  for (size_t i = 0; i < photons.size(); ++i) {
    glm::ivec3 cell = cell_of(photons[i].position);
    buckets[i] = hash(cell.x, cell.y, cell.z);
    ++starts_[buckets[i] + 1];
  }
  for (uint32_t b = 0; b < table_size; ++b) starts_[b + 1] += starts_[b];
  order_.resize(photons.size());
  std::vector<uint32_t> fill(starts_.begin(), starts_.end() - 1);
  for (size_t i = 0; i < photons.size(); ++i) order_[fill[buckets[i]]++] = static_cast<uint32_t>(i);
}

}  // namespace causticbench
