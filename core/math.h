// Small vector helpers shared by the geometry, the tracer and the methods. Geometry runs in float
// (what Embree traces); accumulations that must not lose photons run in double.
#pragma once

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

namespace causticbench {

using Vec3 = glm::vec3;
using Color = glm::vec3;  // linear RGB

inline constexpr float kPi = 3.14159265358979323846f;
inline constexpr double kPiDouble = 3.14159265358979323846;
// The largest coordinate a point of a scene may have (a mesh vertex, a translation, a light or camera
// position): geometry is traced in single precision, whose spacing at 1e6 is 0.06 scene units.
inline constexpr double kMaximumCoordinate = 1e6;

struct Ray {
  Vec3 origin{0.0f};
  Vec3 direction{0.0f, 0.0f, 1.0f};  // unit length
  float t_min = 0.0f;
  float t_max = 1e30f;
};

inline float max_component(const Vec3& v) { return std::max(v.x, std::max(v.y, v.z)); }
inline float luminance(const Color& c) { return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b; }

// Mirror reflection of an incoming direction `d` (pointing towards the surface) about normal `n`.
inline Vec3 reflect(const Vec3& d, const Vec3& n) { return d - 2.0f * glm::dot(d, n) * n; }

// Builds a right-handed orthonormal basis (t, b, n) around the unit vector n (Duff et al. 2017).
inline void orthonormal_basis(const Vec3& n, Vec3& t, Vec3& b) {
  float sign = std::copysign(1.0f, n.z);
  float a = -1.0f / (sign + n.z);
  float c = n.x * n.y * a;
  t = Vec3(1.0f + sign * n.x * n.x * a, sign * c, -sign * n.x);
  b = Vec3(c, sign + n.y * n.y * a, -n.y);
}

}  // namespace causticbench
