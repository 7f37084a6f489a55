// A scene: camera, lights, objects and their animation. Nothing else (see docs/scene-format.md).
#pragma once

#include <string>
#include <vector>

#include "core/camera.h"
#include "core/light.h"
#include "core/material.h"
#include "core/shape.h"
#include "core/transform.h"

namespace causticbench {

struct SceneObject {
  std::string name;
  ShapeDesc shape;
  Material material;
  AnimatedTransform transform;
};

struct Scene {
  std::string source;  // the file it was read from
  std::string name;
  Camera camera;
  std::vector<Light> lights;
  std::vector<SceneObject> objects;
  int frames = 1;      // animation length; frame indices are 0 .. frames-1

  bool has_specular_object() const;
};

// Reads and validates a scene file; every error is an InputError with file, line and column.
Scene load_scene(const std::string& path);
// A scene file's text already read from `path` (assets resolve against path's folder, as load_scene's do).
Scene load_scene_text(const std::string& text, const std::string& path);
Scene load_scene_from_string(const std::string& text, const std::string& name, const std::string& folder);

// Overrides applied after loading (command line or experiment): resolution and frame count.
void set_resolution(Scene& scene, int width, int height);

// Bounding sphere of a posed object, in world space.
struct BoundingSphere {
  Vec3 center{0.0f};
  float radius = 0.0f;
};

// The scene posed at one frame: world transforms, lights, and the bounding spheres that photon
// emission aims at.
struct SceneFrame {
  const Scene* scene = nullptr;
  double frame = 0.0;
  CameraFrame camera;
  std::vector<LightFrame> lights;
  std::vector<Transform> transforms;             // per object
  std::vector<TriangleMesh> world_meshes;        // per object; empty for analytic shapes
  std::vector<BoundingSphere> bounds;            // per object, world space
  BoundingSphere scene_bounds;                   // all objects

  SceneFrame(const Scene& scene, double frame);
  // Objects whose material has a specular part: the ones caustic photons must be aimed at.
  std::vector<int> specular_objects() const;
};

}  // namespace causticbench
