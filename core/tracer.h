// Ray tracing with Embree 3 over one posed frame of a scene. Analytic shapes are Embree user
// geometry intersected exactly in double precision; the rest are triangle meshes.
#pragma once

#include <memory>
#include <vector>

#include <embree3/rtcore.h>

#include "core/scene.h"

namespace causticbench {

struct SurfaceHit {
  float t = 0.0f;
  Vec3 position{0.0f};
  Vec3 geometric_normal{0.0f};  // outward (the side the shape's normals face), unit
  Vec3 shading_normal{0.0f};    // outward, unit; exact for analytic shapes, interpolated for smooth meshes
  int object = -1;
  unsigned primitive = 0;
  int part = 0;                 // an analytic shape's surface (a cup's wall or bottom: shape.h)
  float u = 0.0f, v = 0.0f;     // a triangle's barycentric coordinates of the hit (weights of its 2nd and 3rd vertex)
};

class Tracer {
 public:
  explicit Tracer(const SceneFrame& frame);
  ~Tracer();
  Tracer(const Tracer&) = delete;
  Tracer& operator=(const Tracer&) = delete;

  bool intersect(const Ray& ray, SurfaceHit& hit) const;
  bool occluded(const Vec3& origin, const Vec3& direction, float t_max) const;
  // How the hit's unit shading normal changes as the point moves by `step` along the surface (first
  // order; ray differentials, core/ray_differential.h). Analytic shapes: central differences of their
  // exact normal in double precision; smooth meshes: the interpolated normal's derivative across the
  // triangle; flat faces: zero.
  Vec3 shading_normal_change(const SurfaceHit& hit, const Vec3& step) const;

  const SceneFrame& frame() const { return *frame_; }
  // Offset that moves a ray origin off a surface to avoid self-intersection, in scene units.
  float epsilon() const { return epsilon_; }
  // A ray leaving `hit` in `direction`, nudged off the surface to the side it travels to.
  Ray spawn(const SurfaceHit& hit, const Vec3& direction) const;

  struct AnalyticInstance {
    const ShapeDesc* shape = nullptr;
    glm::dmat4 inverse{1.0};
  };

 private:
  const SceneFrame* frame_;
  RTCScene scene_ = nullptr;
  std::vector<int> geometry_to_object_;
  std::vector<std::unique_ptr<AnalyticInstance>> analytic_;
  float epsilon_ = 1e-4f;
};

// The process-wide Embree device.
RTCDevice embree_device();

}  // namespace causticbench
