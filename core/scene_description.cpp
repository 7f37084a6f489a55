#include "core/scene_description.h"

#include "core/hash.h"

namespace causticbench {

namespace {

using nlohmann::json;

json vector_json(const glm::dvec3& value) { return json::array({value.x, value.y, value.z}); }
// Floats widen to doubles exactly, so the dump is the float's exact value.
json color_json(const Color& value) { return vector_json(glm::dvec3(value)); }

// A track with one key is constant whatever frame that key names, so it is written as its value:
// `direction: [0, -1, 0]` and a single keyframe holding the same direction describe the same light.
json track_json(const Vec3Track& track) {
  if (track.keys.size() == 1) return json{{"value", vector_json(track.keys.front().second)}};
  json keyframes = json::array();
  for (const auto& [frame, value] : track.keys) {
    keyframes.push_back(json{{"frame", frame}, {"value", vector_json(value)}});
  }
  return json{{"keyframes", keyframes}};
}

template <typename Element>
std::string hash_elements(const std::vector<Element>& elements) {
  return hash_bytes(elements.data(), elements.size() * sizeof(Element));
}

// Spelled out rather than light_kind_name's display names, so that a reworded message never changes a key.
std::string light_kind_key(LightKind kind) {
  switch (kind) {
    case LightKind::directional: return "directional";
    case LightKind::point: return "point";
    case LightKind::environment_image: return "environment_image";
    case LightKind::gaussian_spot: return "gaussian_spot";
  }
  return "unknown";
}

void add_mirror_fields(const Material& material, json& description) {
  description["reflectance"] = color_json(material.reflectance);
  description["conductor"] = material.conductor;
  if (material.conductor) {
    description["eta"] = color_json(material.eta);
    description["k"] = color_json(material.k);
  }
}

}  // namespace

json shape_json(const ShapeDesc& shape) {
  json description{{"kind", shape_kind_name(shape.kind)}};
  switch (shape.kind) {
    case ShapeKind::quad: description["size"] = json::array({shape.size.x, shape.size.y}); break;
    case ShapeKind::disk:
    case ShapeKind::sphere: description["radius"] = shape.radius; break;
    case ShapeKind::ring:
      description["radius"] = shape.radius;
      description["height"] = shape.height;
      description["thickness"] = shape.thickness;
      break;
    case ShapeKind::cup:
      description["radius"] = shape.radius;
      description["height"] = shape.height;
      break;
    case ShapeKind::torus:
      description["major_radius"] = shape.major_radius;
      description["minor_radius"] = shape.minor_radius;
      description["segments"] = json::array({shape.segments.x, shape.segments.y});
      break;
    case ShapeKind::box: description["size"] = vector_json(shape.box_size); break;
    case ShapeKind::prism:
      description["side"] = shape.side;
      description["length"] = shape.length;
      break;
    case ShapeKind::paraboloid:
      description["radius"] = shape.radius;
      description["focal_length"] = shape.focal_length;
      break;
    case ShapeKind::water: {
      description["size"] = json::array({shape.size.x, shape.size.y});
      description["resolution"] = json::array({shape.resolution.x, shape.resolution.y});
      json waves = json::array();
      for (const WaterWave& wave : shape.waves) {
        waves.push_back(json{{"amplitude", wave.amplitude},
                             {"wavelength", wave.wavelength},
                             {"direction_degrees", wave.direction_degrees},
                             {"phase_degrees", wave.phase_degrees},
                             {"phase_per_frame_degrees", wave.phase_per_frame_degrees}});
      }
      description["waves"] = waves;
      break;
    }
    case ShapeKind::mesh: {
      description["asset"] = shape.asset;
      // The loaded triangles, not the file: fit_size, smoothing and vertex welding are already in
      // them, and the same name may resolve to another file on another machine or after an edit.
      if (shape.mesh) {
        const TriangleMesh& mesh = *shape.mesh;
        description["vertices"] = mesh.positions.size();
        description["triangles"] = mesh.triangles.size();
        description["smooth"] = mesh.smooth;
        description["positions_hash"] = hash_elements(mesh.positions);
        description["normals_hash"] = hash_elements(mesh.normals);
        description["triangles_hash"] = hash_elements(mesh.triangles);
      }
      break;
    }
  }
  return description;
}

json material_json(const Material& material) {
  json description{{"kind", material_kind_name(material.kind)}};
  switch (material.kind) {
    case MaterialKind::diffuse: description["albedo"] = color_json(material.albedo); break;
    case MaterialKind::glossy:
      description["albedo"] = color_json(material.albedo);
      description["specular"] = color_json(material.specular);
      description["exponent"] = static_cast<double>(material.exponent);
      break;
    case MaterialKind::mirror: add_mirror_fields(material, description); break;
    case MaterialKind::glass:
      description["ior"] = static_cast<double>(material.ior);
      description["absorption"] = color_json(material.absorption);
      break;
    case MaterialKind::diffuse_mirror:
      description["albedo"] = color_json(material.albedo);
      // Its mirror part reflects through Material::mirror_reflectance, conductor Fresnel included.
      add_mirror_fields(material, description);
      break;
  }
  return description;
}

json transform_json(const AnimatedTransform& transform) {
  return json{{"translate", track_json(transform.translate)},
              {"rotate", track_json(transform.rotate)},
              {"scale", track_json(transform.scale)}};
}

json light_json(const Light& light) {
  json description{{"kind", light_kind_key(light.kind)}};
  switch (light.kind) {
    case LightKind::directional:
    case LightKind::gaussian_spot:
      description["direction"] = track_json(light.direction);
      description["irradiance"] = color_json(light.irradiance);
      description["solid_angle"] = light.solid_angle;
      break;
    case LightKind::point:
      description["position"] = track_json(light.position);
      description["intensity"] = color_json(light.intensity);
      description["radius"] = light.radius;
      break;
    case LightKind::environment_image:
      description["image_path"] = light.image_path;
      description["scale"] = light.scale;
      description["rotation_degrees"] = light.rotation_degrees;
      // The pixels as loaded: the same path may hold another image after an edit.
      if (light.environment) {
        description["width"] = light.environment->width();
        description["height"] = light.environment->height();
        description["pixels_hash"] = hash_elements(light.environment->pixels());
      }
      break;
  }
  return description;
}

json object_json(const Scene& scene, int index) {
  const SceneObject& object = scene.objects.at(static_cast<size_t>(index));
  return json{{"name", object.name},
              {"shape", shape_json(object.shape)},
              {"material", material_json(object.material)},
              {"transform", transform_json(object.transform)}};
}

json scene_content_json(const Scene& scene) {
  json objects = json::array(), lights = json::array();
  for (size_t i = 0; i < scene.objects.size(); ++i) objects.push_back(object_json(scene, static_cast<int>(i)));
  for (const Light& light : scene.lights) lights.push_back(light_json(light));
  return json{{"objects", objects}, {"lights", lights}, {"frames", scene.frames}};
}

bool scene_is_static(const Scene& scene) {
  for (const Light& light : scene.lights) {
    if (light.animated()) return false;
  }
  for (const SceneObject& object : scene.objects) {
    if (object.transform.animated() || object.shape.changes_with_frame()) return false;
  }
  return true;
}

}  // namespace causticbench
