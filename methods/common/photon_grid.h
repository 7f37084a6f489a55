// A hashed uniform grid over photons for fixed-radius gathers (the reference's progressive photon
// mapping). Built by a counting sort, so it costs two passes over the photons and no allocation per cell.
#pragma once

#include <cstdint>
#include <vector>

#include "core/photon_tracer.h"

namespace causticbench {

class PhotonGrid {
 public:
  PhotonGrid(const std::vector<Photon>& photons, float cell_size);

  // Calls visit(photon) for every photon within `radius` of `point` (and possibly a few more from
  // hash collisions or corner cells: the caller tests the distance).
  template <typename Visit>
  void for_each_near(const Vec3& point, float radius, Visit visit) const {
    if (photons_.empty()) return;
    glm::ivec3 lower = cell_of(point - Vec3(radius)), upper = cell_of(point + Vec3(radius));
    for (int z = lower.z; z <= upper.z; ++z) {
      for (int y = lower.y; y <= upper.y; ++y) {
        for (int x = lower.x; x <= upper.x; ++x) {
          uint32_t bucket = hash(x, y, z);
          for (uint32_t i = starts_[bucket]; i < starts_[bucket + 1]; ++i) visit(photons_[order_[i]]);
        }
      }
    }
  }

 private:
  glm::ivec3 cell_of(const Vec3& p) const {
    return glm::ivec3(static_cast<int>(std::floor(p.x * inverse_cell_)), static_cast<int>(std::floor(p.y * inverse_cell_)),
                      static_cast<int>(std::floor(p.z * inverse_cell_)));
  }
  uint32_t hash(int x, int y, int z) const {
    uint32_t h = static_cast<uint32_t>(x) * 73856093u ^ static_cast<uint32_t>(y) * 19349663u ^
                 static_cast<uint32_t>(z) * 83492791u;
    return h & mask_;
  }

  const std::vector<Photon>& photons_;
  float inverse_cell_;
  uint32_t mask_ = 0;
  std::vector<uint32_t> starts_;
  std::vector<uint32_t> order_;
};

}  // namespace causticbench
