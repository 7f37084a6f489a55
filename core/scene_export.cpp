#include "core/scene_export.h"

#include <cmath>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/files.h"
#include "core/hash.h"
#include "core/image.h"
#include "core/mesh_file.h"

namespace causticbench {

namespace {

using nlohmann::json;

// Doubles are written by nlohmann::json as the shortest text that reads back to the same double, and
// floats are widened first, so every value reads back exactly.
json vec(const glm::dvec3& v) { return json::array({v.x, v.y, v.z}); }
json vec(const Vec3& v) { return json::array({double(v.x), double(v.y), double(v.z)}); }
json rgb(const Color& c) { return json::array({double(c.r), double(c.g), double(c.b)}); }

json camera_json(const Camera& camera, double frame) {
  json result = {{"type", camera.type == Camera::Type::perspective ? "perspective" : "orthographic"},
                 {"position", vec(camera.position.at(frame))},
                 {"look_at", vec(camera.look_at.at(frame))},
                 {"up", vec(camera.up)},
                 {"resolution", json::array({camera.width, camera.height})}};
  if (camera.type == Camera::Type::perspective) result["fov_degrees"] = camera.fov_degrees;
  else result["view_height"] = camera.view_height;
  return result;
}

json material_map(const Material& material) {
  json result = {{"type", material_kind_name(material.kind)}};
  switch (material.kind) {
    case MaterialKind::diffuse: result["albedo"] = rgb(material.albedo); break;
    case MaterialKind::glossy:
      result["albedo"] = rgb(material.albedo);
      result["specular"] = rgb(material.specular);
      result["exponent"] = double(material.exponent);
      break;
    case MaterialKind::mirror:
      result["reflectance"] = rgb(material.reflectance);
      if (material.conductor) result["conductor"] = {{"eta", rgb(material.eta)}, {"k", rgb(material.k)}};
      break;
    case MaterialKind::glass:
      result["ior"] = double(material.ior);
      result["absorption"] = rgb(material.absorption);
      break;
    case MaterialKind::diffuse_mirror:
      result["albedo"] = rgb(material.albedo);
      result["reflectance"] = rgb(material.reflectance);
      break;
  }
  return result;
}

// The shape map at `frame`; `mesh_file` names the file an imported mesh is written to.
json shape_map(const ShapeDesc& shape, double frame, const std::string& mesh_file) {
  json result = {{"type", shape_kind_name(shape.kind)}};
  switch (shape.kind) {
    case ShapeKind::quad: result["size"] = {shape.size.x, shape.size.y}; break;
    case ShapeKind::disk:
    case ShapeKind::sphere: result["radius"] = shape.radius; break;
    case ShapeKind::ring:
      result.update({{"radius", shape.radius}, {"height", shape.height}, {"thickness", shape.thickness}});
      break;
    case ShapeKind::cup: result.update({{"radius", shape.radius}, {"height", shape.height}}); break;
    case ShapeKind::torus:
      result.update({{"major_radius", shape.major_radius},
                     {"minor_radius", shape.minor_radius},
                     {"segments", {shape.segments.x, shape.segments.y}}});
      break;
    case ShapeKind::box: result["size"] = vec(shape.box_size); break;
    case ShapeKind::prism: result.update({{"side", shape.side}, {"length", shape.length}}); break;
    case ShapeKind::paraboloid: result.update({{"focal_length", shape.focal_length}, {"radius", shape.radius}}); break;
    case ShapeKind::water: {
      result.update({{"size", {shape.size.x, shape.size.y}}, {"resolution", {shape.resolution.x, shape.resolution.y}}});
      json waves = json::array();
      for (const WaterWave& wave : shape.waves) {
        // The phase at this frame, as the height field computes it (phase + frame x phase per frame), so
        // that frame 0 of the written scene is this frame; folded into a turn only beyond the range the
        // reader accepts (then equal up to rounding, no longer bit for bit).
        double phase = wave.phase_degrees + frame * wave.phase_per_frame_degrees;
        if (std::abs(phase) > 1e6) phase = std::fmod(phase, 360.0);
        waves.push_back({{"amplitude", wave.amplitude},
                         {"wavelength", wave.wavelength},
                         {"direction_degrees", wave.direction_degrees},
                         {"phase_degrees", phase}});
      }
      result["waves"] = waves;
      break;
    }
    case ShapeKind::mesh:
      result.update({{"asset", mesh_file}, {"smooth_normals", shape.mesh ? shape.mesh->smooth : true}, {"fit_size", 0.0}});
      break;
  }
  return result;
}

// The object's transform at the frame, as translate, rotate and scale: the reader builds the same
// matrix from the same three values.
json transform_map(const AnimatedTransform& transform, double frame) {
  return {{"translate", vec(transform.translate.at(frame))},
          {"rotate", vec(transform.rotate.at(frame))},
          {"scale", vec(transform.scale.at(frame))}};
}

json light_map(const Light& light, double frame, const std::string& image_file) {
  json result = json::object();
  if (!light.name.empty()) result["name"] = light.name;
  switch (light.kind) {
    case LightKind::directional:
      result.update({{"type", "directional"},
                     {"direction", vec(light.direction.at(frame))},
                     {"irradiance", rgb(light.irradiance)},
                     {"solid_angle_sr", light.solid_angle}});
      break;
    case LightKind::point:
      result.update({{"type", "point"},
                     {"position", vec(light.position.at(frame))},
                     {"intensity", rgb(light.intensity)},
                     {"radius", light.radius}});
      break;
    case LightKind::environment_image:
      // The map's pixels are written already scaled, so the scale is 1.
      result.update({{"type", "environment"}, {"image", image_file}, {"scale", 1.0}, {"rotation_degrees", light.rotation_degrees}});
      break;
    case LightKind::gaussian_spot:
      result.update({{"type", "environment"},
                     {"procedural", "gaussian_spot"},
                     {"direction", vec(light.direction.at(frame))},
                     {"irradiance", rgb(light.irradiance)},
                     {"solid_angle_sr", light.solid_angle}});
      break;
  }
  return result;
}

json matrix_rows(const glm::dmat4& matrix) {
  json rows = json::array();
  for (int row = 0; row < 4; ++row) rows.push_back({matrix[0][row], matrix[1][row], matrix[2][row], matrix[3][row]});
  return rows;
}

// world.json's name of a light kind (scene.json writes the scene format's `type` and `procedural`).
const char* world_light_type(LightKind kind) {
  switch (kind) {
    case LightKind::directional: return "directional";
    case LightKind::point: return "point";
    case LightKind::environment_image: return "environment_image";
    case LightKind::gaussian_spot: return "gaussian_spot";
  }
  return "?";
}

json posed_light(const LightFrame& posed) {
  const Light& light = *posed.light;
  json result = {{"type", world_light_type(light.kind)}};
  if (!light.name.empty()) result["name"] = light.name;
  // A direction for the lights that have one: an image environment has the whole sphere.
  if (light.kind == LightKind::directional || light.kind == LightKind::gaussian_spot)
    result["direction_to_light"] = vec(posed.direction_to_light);
  switch (light.kind) {
    case LightKind::directional:
      result.update({{"irradiance", rgb(light.irradiance)}, {"solid_angle_sr", light.solid_angle}, {"cos_cone", posed.cos_cone}});
      break;
    case LightKind::point:
      result.update({{"position", vec(posed.position)}, {"intensity", rgb(light.intensity)}, {"radius", posed.radius}});
      break;
    case LightKind::environment_image: break;  // completed by the caller with the image's file
    case LightKind::gaussian_spot:
      result.update({{"irradiance", rgb(light.irradiance)}, {"solid_angle_sr", light.solid_angle}, {"sigma_radians", posed.spot_sigma}});
      break;
  }
  return result;
}

}  // namespace

SceneExporter::SceneExporter(std::string folder) : folder_(std::move(folder)) {}

std::string SceneExporter::write(const SceneFrame& frame) {
  const Scene& scene = *frame.scene;
  auto write_once = [&](const std::string& file, const std::string& source, const std::function<void(const std::string&)>& writer) {
    auto it = written_.find(file);
    if (it != written_.end() && it->second == source) return;
    writer(folder_ + "/" + file);
    written_[file] = source;
  };

  json lights = json::array(), posed_lights = json::array();
  for (size_t i = 0; i < scene.lights.size(); ++i) {
    const Light& light = scene.lights[i];
    const std::string image_file = fmt::format("environment_{}.exr", i);
    lights.push_back(light_map(light, frame.frame, image_file));
    json posed = posed_light(frame.lights[i]);
    if (light.kind == LightKind::environment_image) {
      write_once(image_file, "static", [&](const std::string& path) {
        const EnvironmentMap& map = *light.environment;
        Image image(map.width(), map.height(), 3);
        image.values() = map.pixels();
        write_exr(image, path);
      });
      posed.update({{"image", image_file}, {"rotation_degrees", light.rotation_degrees}});
    }
    posed_lights.push_back(posed);
  }

  json objects = json::array(), world_objects = json::array();
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    const SceneObject& object = scene.objects[i];
    const std::string mesh_file = fmt::format("mesh_{}.ply", i);
    if (object.shape.kind == ShapeKind::mesh) {
      write_once(mesh_file, "static", [&](const std::string& path) { write_mesh_ply(*object.shape.mesh, path); });
    }
    const json shape = shape_map(object.shape, frame.frame, mesh_file);
    const json material = material_map(object.material);
    objects.push_back({{"name", object.name}, {"shape", shape}, {"material", material},
                       {"transform", transform_map(object.transform, frame.frame)}});
    const BoundingSphere& bounds = frame.bounds[i];
    json world = {{"name", object.name},
                  {"shape", shape},
                  {"material", material},
                  {"object_to_world", matrix_rows(frame.transforms[i].matrix)},
                  {"bounds", {{"center", vec(bounds.center)}, {"radius", bounds.radius}}},
                  {"makes_caustics", object.material.is_specular()},
                  {"receives_caustics", object.material.receives_caustics()}};
    if (!object.shape.is_analytic()) {
      const std::string triangles_file = fmt::format("world_{}.ply", i);
      // Rewritten when the object moves or its surface changes with the frame (moving water).
      const std::string source = hash_json({matrix_rows(frame.transforms[i].matrix),
                                            object.shape.changes_with_frame() ? frame.frame : 0.0});
      write_once(triangles_file, source, [&](const std::string& path) { write_mesh_ply(frame.world_meshes[i], path); });
      world.update({{"triangles", triangles_file}, {"smooth_normals", frame.world_meshes[i].smooth}});
    }
    world_objects.push_back(world);
  }

  const json camera = camera_json(scene.camera, frame.frame);
  json scene_file = {{"name", scene.name}, {"frames", 1}, {"camera", camera}, {"lights", lights}, {"objects", objects}};
  const json frame_index = frame.frame == std::floor(frame.frame) ? json(static_cast<int64_t>(frame.frame)) : json(frame.frame);
  json world_file = {{"frame", frame_index},
                     {"scene", "scene.json"},
                     {"camera", camera},
                     {"lights", posed_lights},
                     {"objects", world_objects},
                     {"scene_bounds", {{"center", vec(frame.scene_bounds.center)}, {"radius", frame.scene_bounds.radius}}}};
  write_text_atomically(world_path(), world_file.dump(1) + "\n");
  write_text_atomically(scene_path(), scene_file.dump(1) + "\n");
  return scene_path();
}

}  // namespace causticbench
