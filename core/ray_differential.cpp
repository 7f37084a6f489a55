#include "core/ray_differential.h"

#include <cmath>

namespace causticbench {

void transfer_differential(RayDifferential& differential, const Vec3& d, float t, const Vec3& n) {
  const float facing = glm::dot(d, n);
  for (int k = 0; k < 2; ++k) {
    Vec3& dp = k == 0 ? differential.dp_du : differential.dp_dv;
    const Vec3& dd = k == 0 ? differential.dd_du : differential.dd_dv;
    const Vec3 moved = dp + t * dd;
    const float dt = facing != 0.0f ? -glm::dot(moved, n) / facing : 0.0f;
    dp = moved + dt * d;
  }
}

void reflect_differential(RayDifferential& differential, const Vec3& d, const Vec3& n, const Vec3& dn_du,
                          const Vec3& dn_dv) {
  const float dn = glm::dot(d, n);
  for (int k = 0; k < 2; ++k) {
    Vec3& dd = k == 0 ? differential.dd_du : differential.dd_dv;
    const Vec3& dnormal = k == 0 ? dn_du : dn_dv;
    const float change = glm::dot(dd, n) + glm::dot(d, dnormal);
    dd = dd - 2.0f * (dn * dnormal + change * n);
  }
}

void refract_differential(RayDifferential& differential, const Vec3& d, const Vec3& n, const Vec3& dn_du,
                          const Vec3& dn_dv, float eta) {
  const float cos_incident = -glm::dot(d, n);
  const float sin2_transmitted = (1.0f - cos_incident * cos_incident) / (eta * eta);
  if (sin2_transmitted >= 1.0f) return;
  const float cos_transmitted = std::sqrt(1.0f - sin2_transmitted);
  const float mu = cos_incident / eta - cos_transmitted;
  for (int k = 0; k < 2; ++k) {
    Vec3& dd = k == 0 ? differential.dd_du : differential.dd_dv;
    const Vec3& dnormal = k == 0 ? dn_du : dn_dv;
    const float d_cos_incident = -(glm::dot(dd, n) + glm::dot(d, dnormal));
    // c_t^2 = 1 - (1 - c_i^2) / eta^2, so d c_t = c_i d c_i / (eta^2 c_t).
    const float d_cos_transmitted = cos_transmitted > 0.0f ? cos_incident * d_cos_incident / (eta * eta * cos_transmitted) : 0.0f;
    const float d_mu = d_cos_incident / eta - d_cos_transmitted;
    dd = dd / eta + d_mu * n + mu * dnormal;
  }
}

}  // namespace causticbench
