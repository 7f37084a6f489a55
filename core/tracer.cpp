#include "core/tracer.h"

#include <limits>
#include <stdexcept>

#include <fmt/format.h>

namespace causticbench {

namespace {

void report_embree_error(void*, RTCError code, const char* message) {
  if (code == RTC_ERROR_NONE) return;
  fmt::print(stderr, "embree error {}: {}\n", static_cast<int>(code), message ? message : "");
}

using Instance = Tracer::AnalyticInstance;

void analytic_bounds_callback(const RTCBoundsFunctionArguments* args) {
  const Instance* instance = static_cast<const Instance*>(args->geometryUserPtr);
  glm::dvec3 lower, upper;
  analytic_bounds(*instance->shape, lower, upper);
  glm::dmat4 matrix = glm::inverse(instance->inverse);
  glm::dvec3 world_lower(1e300), world_upper(-1e300);
  for (int corner = 0; corner < 8; ++corner) {
    glm::dvec3 p((corner & 1) ? upper.x : lower.x, (corner & 2) ? upper.y : lower.y, (corner & 4) ? upper.z : lower.z);
    glm::dvec3 world = glm::dvec3(matrix * glm::dvec4(p, 1.0));
    world_lower = glm::min(world_lower, world);
    world_upper = glm::max(world_upper, world);
  }
  RTCBounds* bounds = args->bounds_o;
  bounds->lower_x = static_cast<float>(world_lower.x);
  bounds->lower_y = static_cast<float>(world_lower.y);
  bounds->lower_z = static_cast<float>(world_lower.z);
  bounds->upper_x = static_cast<float>(world_upper.x);
  bounds->upper_y = static_cast<float>(world_upper.y);
  bounds->upper_z = static_cast<float>(world_upper.z);
}

bool intersect_instance(const Instance& instance, const RTCRay& ray, AnalyticHit& hit) {
  glm::dvec3 origin(ray.org_x, ray.org_y, ray.org_z), direction(ray.dir_x, ray.dir_y, ray.dir_z);
  // An affine map keeps the ray parameter t, so the object-space t is the world-space t.
  glm::dvec3 local_origin = glm::dvec3(instance.inverse * glm::dvec4(origin, 1.0));
  glm::dvec3 local_direction = glm::dvec3(instance.inverse * glm::dvec4(direction, 0.0));
  return intersect_analytic(*instance.shape, local_origin, local_direction, ray.tnear, ray.tfar, hit);
}

// Called by rtcIntersect1 only (N == 1), so the packet is a plain RTCRayHit.
void analytic_intersect_callback(const RTCIntersectFunctionNArguments* args) {
  if (!args->valid[0]) return;
  const Instance* instance = static_cast<const Instance*>(args->geometryUserPtr);
  RTCRayHit* rayhit = reinterpret_cast<RTCRayHit*>(args->rayhit);
  AnalyticHit hit;
  if (!intersect_instance(*instance, rayhit->ray, hit)) return;
  rayhit->ray.tfar = static_cast<float>(hit.t);
  rayhit->hit.u = static_cast<float>(hit.surface);  // which part of the shape; read back for the normal
  rayhit->hit.v = 0.0f;
  rayhit->hit.Ng_x = 0.0f;
  rayhit->hit.Ng_y = 1.0f;
  rayhit->hit.Ng_z = 0.0f;
  rayhit->hit.primID = args->primID;
  rayhit->hit.geomID = args->geomID;
  rayhit->hit.instID[0] = args->context->instID[0];
}

void analytic_occluded_callback(const RTCOccludedFunctionNArguments* args) {
  if (!args->valid[0]) return;
  const Instance* instance = static_cast<const Instance*>(args->geometryUserPtr);
  RTCRay* ray = reinterpret_cast<RTCRay*>(args->ray);
  AnalyticHit hit;
  if (intersect_instance(*instance, *ray, hit)) ray->tfar = -std::numeric_limits<float>::infinity();
}

}  // namespace

RTCDevice embree_device() {
  static RTCDevice device = [] {
    RTCDevice created = rtcNewDevice(nullptr);
    if (!created) throw std::runtime_error("cannot create the Embree device");
    rtcSetDeviceErrorFunction(created, report_embree_error, nullptr);
    return created;
  }();
  return device;
}

Tracer::Tracer(const SceneFrame& frame) : frame_(&frame) {
  RTCDevice device = embree_device();
  scene_ = rtcNewScene(device);
  rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);
  rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);
  const Scene& scene = *frame.scene;
  for (size_t index = 0; index < scene.objects.size(); ++index) {
    const SceneObject& object = scene.objects[index];
    RTCGeometry geometry;
    if (object.shape.is_analytic()) {
      geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
      auto instance = std::make_unique<Instance>();
      instance->shape = &object.shape;
      instance->inverse = frame.transforms[index].inverse;
      rtcSetGeometryUserPrimitiveCount(geometry, 1);
      rtcSetGeometryUserData(geometry, instance.get());
      rtcSetGeometryBoundsFunction(geometry, analytic_bounds_callback, nullptr);
      rtcSetGeometryIntersectFunction(geometry, analytic_intersect_callback);
      rtcSetGeometryOccludedFunction(geometry, analytic_occluded_callback);
      analytic_.push_back(std::move(instance));
    } else {
      const TriangleMesh& mesh = frame.world_meshes[index];
      geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
      float* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0,
                                                                     RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                                                     mesh.positions.size()));
      for (size_t v = 0; v < mesh.positions.size(); ++v) {
        vertices[3 * v] = mesh.positions[v].x;
        vertices[3 * v + 1] = mesh.positions[v].y;
        vertices[3 * v + 2] = mesh.positions[v].z;
      }
      unsigned* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
          geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), mesh.triangles.size()));
      for (size_t t = 0; t < mesh.triangles.size(); ++t) {
        indices[3 * t] = mesh.triangles[t].x;
        indices[3 * t + 1] = mesh.triangles[t].y;
        indices[3 * t + 2] = mesh.triangles[t].z;
      }
    }
    rtcCommitGeometry(geometry);
    unsigned id = rtcAttachGeometry(scene_, geometry);
    rtcReleaseGeometry(geometry);
    if (geometry_to_object_.size() <= id) geometry_to_object_.resize(id + 1, -1);
    geometry_to_object_[id] = static_cast<int>(index);
  }
  rtcCommitScene(scene_);
  epsilon_ = std::max(1e-6f, frame.scene_bounds.radius * 1e-5f);
}

Tracer::~Tracer() {
  if (scene_) rtcReleaseScene(scene_);
}

bool Tracer::intersect(const Ray& ray, SurfaceHit& hit) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rayhit;
  rayhit.ray.org_x = ray.origin.x;
  rayhit.ray.org_y = ray.origin.y;
  rayhit.ray.org_z = ray.origin.z;
  rayhit.ray.dir_x = ray.direction.x;
  rayhit.ray.dir_y = ray.direction.y;
  rayhit.ray.dir_z = ray.direction.z;
  rayhit.ray.tnear = ray.t_min;
  rayhit.ray.tfar = ray.t_max;
  rayhit.ray.mask = 0xFFFFFFFFu;
  rayhit.ray.flags = 0;
  rayhit.ray.time = 0.0f;
  rayhit.ray.id = 0;
  rayhit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rayhit.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(scene_, &context, &rayhit);
  if (rayhit.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
  int object = geometry_to_object_[rayhit.hit.geomID];
  hit.t = rayhit.ray.tfar;
  hit.object = object;
  hit.primitive = rayhit.hit.primID;
  hit.position = ray.origin + hit.t * ray.direction;
  const SceneObject& scene_object = frame_->scene->objects[object];
  if (scene_object.shape.is_analytic()) {
    const Transform& transform = frame_->transforms[object];
    glm::dvec3 local = glm::dvec3(transform.inverse * glm::dvec4(glm::dvec3(ray.origin) + glm::dvec3(ray.direction) *
                                                                     static_cast<double>(hit.t), 1.0));
    hit.part = static_cast<int>(rayhit.hit.u);
    glm::dvec3 normal = analytic_normal(scene_object.shape, hit.part, local);
    hit.geometric_normal = hit.shading_normal = transform.normal(Vec3(normal));
  } else {
    const TriangleMesh& mesh = frame_->world_meshes[object];
    const glm::uvec3& triangle = mesh.triangles[hit.primitive];
    Vec3 p0 = mesh.positions[triangle.x], p1 = mesh.positions[triangle.y], p2 = mesh.positions[triangle.z];
    hit.geometric_normal = glm::normalize(glm::cross(p1 - p0, p2 - p0));
    hit.u = rayhit.hit.u, hit.v = rayhit.hit.v;
    if (mesh.smooth) {
      float u = rayhit.hit.u, v = rayhit.hit.v;
      Vec3 n = (1.0f - u - v) * mesh.normals[triangle.x] + u * mesh.normals[triangle.y] + v * mesh.normals[triangle.z];
      hit.shading_normal = glm::normalize(n);
    } else {
      hit.shading_normal = hit.geometric_normal;
    }
  }
  return true;
}

Vec3 Tracer::shading_normal_change(const SurfaceHit& hit, const Vec3& step) const {
  const SceneObject& scene_object = frame_->scene->objects[hit.object];
  if (scene_object.shape.is_analytic()) {
    const Transform& transform = frame_->transforms[hit.object];
    const glm::dvec3 local = glm::dvec3(transform.inverse * glm::dvec4(glm::dvec3(hit.position), 1.0));
    const glm::dvec3 local_step = glm::dvec3(transform.inverse * glm::dvec4(glm::dvec3(step), 0.0));
    // The world normal's unnormalised field is N g(local) with N the inverse transpose; along the step it
    // changes by N gradient local_step, and the unit normal by that less its part along the normal, over |g|.
    const AffineNormal field = analytic_normal_field(scene_object.shape, hit.part);
    const glm::dmat3 normal_matrix = glm::transpose(glm::dmat3(transform.inverse));
    const glm::dvec3 raw = normal_matrix * (field.gradient * local + field.offset);
    const double length = glm::length(raw);
    if (!(length > 0.0)) return Vec3(0.0f);
    const glm::dvec3 unit = raw / length;
    const glm::dvec3 raw_change = normal_matrix * (field.gradient * local_step);
    return Vec3((raw_change - unit * glm::dot(unit, raw_change)) / length);
  }
  const TriangleMesh& mesh = frame_->world_meshes[hit.object];
  if (!mesh.smooth) return Vec3(0.0f);
  const glm::uvec3& triangle = mesh.triangles[hit.primitive];
  const Vec3 e1 = mesh.positions[triangle.y] - mesh.positions[triangle.x];
  const Vec3 e2 = mesh.positions[triangle.z] - mesh.positions[triangle.x];
  // The step in barycentric coordinates: least squares of step = a e1 + b e2 (exact for a step in the plane).
  const float g11 = glm::dot(e1, e1), g12 = glm::dot(e1, e2), g22 = glm::dot(e2, e2);
  const float determinant = g11 * g22 - g12 * g12;
  if (!(determinant > 0.0f)) return Vec3(0.0f);
  const float r1 = glm::dot(step, e1), r2 = glm::dot(step, e2);
  const float a = (g22 * r1 - g12 * r2) / determinant, b = (g11 * r2 - g12 * r1) / determinant;
  const Vec3& n0 = mesh.normals[triangle.x];
  const Vec3 raw = (1.0f - hit.u - hit.v) * n0 + hit.u * mesh.normals[triangle.y] + hit.v * mesh.normals[triangle.z];
  const Vec3 raw_change = a * (mesh.normals[triangle.y] - n0) + b * (mesh.normals[triangle.z] - n0);
  const float length = glm::length(raw);
  if (!(length > 0.0f)) return Vec3(0.0f);
  const Vec3 unit = raw / length;
  return (raw_change - unit * glm::dot(unit, raw_change)) / length;
}

bool Tracer::occluded(const Vec3& origin, const Vec3& direction, float t_max) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay ray;
  ray.org_x = origin.x;
  ray.org_y = origin.y;
  ray.org_z = origin.z;
  ray.dir_x = direction.x;
  ray.dir_y = direction.y;
  ray.dir_z = direction.z;
  ray.tnear = 0.0f;
  ray.tfar = t_max;
  ray.mask = 0xFFFFFFFFu;
  ray.flags = 0;
  ray.time = 0.0f;
  ray.id = 0;
  rtcOccluded1(scene_, &context, &ray);
  return ray.tfar < 0.0f;
}

Ray Tracer::spawn(const SurfaceHit& hit, const Vec3& direction) const {
  Ray ray;
  float side = glm::dot(direction, hit.geometric_normal) >= 0.0f ? 1.0f : -1.0f;
  ray.origin = hit.position + hit.geometric_normal * (side * epsilon_);
  ray.direction = direction;
  ray.t_min = 0.0f;
  return ray;
}

}  // namespace causticbench
