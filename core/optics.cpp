#include "core/optics.h"

namespace causticbench {

float fresnel_dielectric(float cos_incident, float eta) {
  cos_incident = std::clamp(cos_incident, 0.0f, 1.0f);
  float sin2_transmitted = (1.0f - cos_incident * cos_incident) / (eta * eta);
  if (sin2_transmitted >= 1.0f) return 1.0f;
  float cos_transmitted = std::sqrt(1.0f - sin2_transmitted);
  float parallel = (eta * cos_incident - cos_transmitted) / (eta * cos_incident + cos_transmitted);
  float perpendicular = (cos_incident - eta * cos_transmitted) / (cos_incident + eta * cos_transmitted);
  return 0.5f * (parallel * parallel + perpendicular * perpendicular);
}

namespace {

// pbrt-v3's FrConductor for one channel (exact for an interface from a dielectric of index 1).
float fresnel_conductor_channel(float cos_i, float eta, float k) {
  float cos2 = cos_i * cos_i;
  float sin2 = 1.0f - cos2;
  float eta2 = eta * eta;
  float k2 = k * k;
  float t0 = eta2 - k2 - sin2;
  float a2plusb2 = std::sqrt(t0 * t0 + 4.0f * eta2 * k2);
  float t1 = a2plusb2 + cos2;
  float a = std::sqrt(std::max(0.0f, 0.5f * (a2plusb2 + t0)));
  float t2 = 2.0f * cos_i * a;
  float rs = (t1 - t2) / (t1 + t2);
  float t3 = cos2 * a2plusb2 + sin2 * sin2;
  float t4 = t2 * sin2;
  float rp = rs * (t3 - t4) / (t3 + t4);
  return 0.5f * (rp + rs);
}

}  // namespace

Color fresnel_conductor(float cos_incident, const Color& eta, const Color& k) {
  cos_incident = std::clamp(cos_incident, 0.0f, 1.0f);
  return Color(fresnel_conductor_channel(cos_incident, eta.r, k.r),
               fresnel_conductor_channel(cos_incident, eta.g, k.g),
               fresnel_conductor_channel(cos_incident, eta.b, k.b));
}

bool refract(const Vec3& d, const Vec3& n, float eta, Vec3& transmitted) {
  float cos_incident = -glm::dot(d, n);
  float sin2_transmitted = (1.0f - cos_incident * cos_incident) / (eta * eta);
  if (sin2_transmitted >= 1.0f) return false;
  float cos_transmitted = std::sqrt(1.0f - sin2_transmitted);
  transmitted = glm::normalize(d / eta + (cos_incident / eta - cos_transmitted) * n);
  return true;
}

}  // namespace causticbench
