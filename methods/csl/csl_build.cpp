// csl's build in the build cache: what determines it (build_dependencies) and its files (save_build,
// load_build; the format is methods/csl/build_file.h). The sets of every light direction, and for a
// dynamic light the matches and triples, are computed once per object, light-direction set and build
// knobs, whatever the camera, receivers or experiment.
#include <filesystem>
#include <fstream>

#include <fmt/format.h>

#include "core/files.h"
#include "core/scene_description.h"
#include "methods/csl/build_file.h"
#include "methods/csl/csl.h"

namespace causticbench {

using namespace csl;

std::optional<nlohmann::json> CslMethod::build_dependencies(const PrepareContext& context, const ParamSet& build) const {
  std::unique_ptr<SphericalMesh> mesh;
  const Plan plan = make_plan(context, build, mesh);
  nlohmann::json objects = nlohmann::json::array();
  for (size_t i = 0; i < plan.objects.size(); ++i) {
    const SceneObject& source = context.scene.objects[plan.objects[i].object];
    const glm::dvec3 scale = source.transform.scale.at(0.0);
    nlohmann::json directions = {{"kind", plan.objects[i].set_kind}};
    if (plan.dynamic[i]) {
      directions["level"] = plan.dynamic[i]->level;
      directions["facets"] = plan.facets[i];
      // Which matching made the pairs and triples (methods/csl/tracking.h), so that a build stored by
      // an earlier one is computed again, not loaded: 2 since axes are compared at the point nearest
      // the object's centre with their convergence angles.
      directions["matching"] = 2;
    } else {
      nlohmann::json list = nlohmann::json::array();
      for (const Vec3& d : plan.static_directions[i]) list.push_back({d.x, d.y, d.z});
      directions["directions"] = list;
    }
    objects.push_back({{"shape", shape_json(source.shape)},
                       {"material", material_json(source.material)},
                       {"scale", {scale.x, scale.y, scale.z}},
                       {"light_directions", directions}});
  }
  return nlohmann::json{{"objects", objects}, {"build", build.to_json()}};
}

void CslMethod::save_build(const std::string& folder) const {
  nlohmann::json meta = nlohmann::json::array();
  for (size_t i = 0; i < objects_.size(); ++i) {
    const ObjectSets& object = objects_[i];
    const std::string name = fmt::format("object_{}.bin", i);
    ObjectBuild build;
    build.sets = object.sets;
    build.dynamic = object.dynamic;
    write_object_build((std::filesystem::path(folder) / name).string(), build);
    meta.push_back({{"file", name}, {"object", object.name}, {"light_sample_set", object.set_kind}});
  }
  write_text_atomically((std::filesystem::path(folder) / "objects.json").string(), meta.dump(2) + "\n");
}

void CslMethod::load_build(const PrepareContext& context, const ParamSet& build, const std::string& folder) {
  scene_ = &context.scene;
  frame_.clear();
  mesh_.reset();
  forget_gpu_images();
  Plan plan = make_plan(context, build, mesh_);
  objects_ = std::move(plan.objects);
  for (size_t i = 0; i < objects_.size(); ++i) {
    const std::string path = (std::filesystem::path(folder) / fmt::format("object_{}.bin", i)).string();
    ObjectBuild stored = read_object_build(path);
    if (static_cast<bool>(stored.dynamic) != static_cast<bool>(plan.dynamic[i]) ||
        (!stored.dynamic && stored.sets.size() != plan.static_directions[i].size()) ||
        (stored.dynamic && stored.dynamic->facets.size() != plan.facets[i].size())) {
      throw std::runtime_error(path + ": not the sets this build plans for object '" + objects_[i].name + "'");
    }
    objects_[i].sets = std::move(stored.sets);
    objects_[i].dynamic = std::move(stored.dynamic);
    // A stored build is judged as a computed one: one without any spot light is refused the same way.
    check_some_spot_light(objects_[i].name, objects_[i].dynamic ? objects_[i].dynamic->sets : objects_[i].sets, build);
  }
  count_rays();
}

}  // namespace causticbench
