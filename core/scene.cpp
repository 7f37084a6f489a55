#include "core/scene.h"

#include <filesystem>

#include <fmt/format.h>

#include "core/files.h"

namespace causticbench {

bool Scene::has_specular_object() const {
  for (const SceneObject& object : objects) {
    if (object.material.is_specular()) return true;
  }
  return false;
}

namespace {

Scene read_scene(const ConfigNode& root, const std::string& folder) {
  Scene scene;
  scene.source = root.file();
  if (!root.is_map()) root.fail_here("a scene map with camera, lights and objects", root.describe_value());
  scene.name = root.string_or("name", std::filesystem::path(root.file()).stem().string());
  scene.frames = root.integer_or("frames", 1, 1, 1000000);
  ConfigNode camera = root.child("camera");
  scene.camera = read_camera(camera);
  // Every frame the scene can render, so that no frame of an animation reaches the tracer degenerate.
  check_camera_at_every_frame(scene.camera, scene.frames, camera);
  ConfigNode lights = root.child("lights");
  if (lights.size() == 0) lights.fail_here("at least one light", "an empty list");
  for (size_t i = 0; i < lights.size(); ++i) scene.lights.push_back(read_light(lights.at(i), folder));
  ConfigNode objects = root.child("objects");
  if (objects.size() == 0) objects.fail_here("at least one object", "an empty list");
  for (size_t i = 0; i < objects.size(); ++i) {
    ConfigNode node = objects.at(i);
    SceneObject object;
    object.name = node.string_or("name", fmt::format("object{}", i));
    object.shape = read_shape(node.child("shape"), folder);
    object.material = read_material(node.child("material"));
    object.transform = read_animated_transform(node);
    if (object.material.kind == MaterialKind::glass &&
        (object.shape.kind == ShapeKind::quad || object.shape.kind == ShapeKind::disk ||
         object.shape.kind == ShapeKind::paraboloid || object.shape.kind == ShapeKind::cup ||
         (object.shape.kind == ShapeKind::ring && object.shape.thickness == 0.0))) {
      node.fail("material", "glass only on closed shapes (sphere, solid ring, torus, box, prism, mesh, water)",
                "glass on an open " + shape_kind_name(object.shape.kind));
    }
    node.finish();
    scene.objects.push_back(std::move(object));
  }
  root.finish();
  return scene;
}

BoundingSphere sphere_around(const std::vector<Vec3>& points) {
  Vec3 lower(1e30f), upper(-1e30f);
  for (const Vec3& p : points) {
    lower = glm::min(lower, p);
    upper = glm::max(upper, p);
  }
  BoundingSphere sphere{(lower + upper) * 0.5f, 0.0f};
  for (const Vec3& p : points) sphere.radius = std::max(sphere.radius, glm::length(p - sphere.center));
  sphere.radius *= 1.0001f;
  return sphere;
}

}  // namespace

Scene load_scene(const std::string& path) { return load_scene_text(read_text(path), path); }

Scene load_scene_text(const std::string& text, const std::string& path) {
  std::string folder = std::filesystem::path(path).parent_path().string();
  return read_scene(ConfigNode::load_string(text, path), folder.empty() ? "." : folder);
}

Scene load_scene_from_string(const std::string& text, const std::string& name, const std::string& folder) {
  return read_scene(ConfigNode::load_string(text, name), folder);
}

void set_resolution(Scene& scene, int width, int height) {
  scene.camera.width = width;
  scene.camera.height = height;
}

SceneFrame::SceneFrame(const Scene& scene_in, double frame_in)
    : scene(&scene_in), frame(frame_in), camera(scene_in.camera, frame_in) {
  for (const Light& light : scene->lights) lights.push_back(pose_light(light, frame));
  std::vector<Vec3> all_corners;
  for (const SceneObject& object : scene->objects) {
    Transform transform = object.transform.at(frame);
    transforms.push_back(transform);
    std::vector<Vec3> points;
    if (object.shape.is_analytic()) {
      world_meshes.emplace_back();
      glm::dvec3 lower, upper;
      analytic_bounds(object.shape, lower, upper);
      for (int corner = 0; corner < 8; ++corner) {
        glm::dvec3 p((corner & 1) ? upper.x : lower.x, (corner & 2) ? upper.y : lower.y, (corner & 4) ? upper.z : lower.z);
        points.push_back(transform.point(Vec3(p)));
      }
      // The tightest sphere around the analytic shape in object space, then transformed.
      glm::dvec3 center = (lower + upper) * 0.5;
      double radius = 0.0;
      if (object.shape.kind == ShapeKind::sphere) {
        center = glm::dvec3(0.0);
        radius = object.shape.radius;
      } else {
        double half_height = (upper.y - lower.y) * 0.5;
        radius = std::sqrt(object.shape.radius * object.shape.radius + half_height * half_height);
      }
      BoundingSphere sphere{transform.point(Vec3(center)),
                            static_cast<float>(radius * transform.max_scale() * 1.0001)};
      bounds.push_back(sphere);
    } else {
      TriangleMesh mesh = tessellate(object.shape, frame);
      for (Vec3& p : mesh.positions) p = transform.point(p);
      for (Vec3& n : mesh.normals) n = transform.normal(n);
      bounds.push_back(sphere_around(mesh.positions));
      points = mesh.positions;
      world_meshes.push_back(std::move(mesh));
    }
    const BoundingSphere& sphere = bounds.back();
    for (int axis = 0; axis < 3; ++axis) {
      for (float sign : {-1.0f, 1.0f}) {
        Vec3 offset(0.0f);
        offset[axis] = sign * sphere.radius;
        all_corners.push_back(sphere.center + offset);
      }
    }
  }
  scene_bounds = sphere_around(all_corners);
}

std::vector<int> SceneFrame::specular_objects() const {
  std::vector<int> result;
  for (size_t i = 0; i < scene->objects.size(); ++i) {
    if (scene->objects[i].material.is_specular()) result.push_back(static_cast<int>(i));
  }
  return result;
}

}  // namespace causticbench
