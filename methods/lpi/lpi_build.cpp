// lpi's build: which light samples each object needs (plan), and the build cache's view of them:
// what determines them (build_dependencies) and their files (save_build, load_build).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <cstring>
#include <fstream>

#include <fmt/format.h>

#include "core/files.h"
#include "core/errors.h"
#include "core/scene_description.h"
#include "methods/lpi/environment.h"
#include "methods/lpi/gpu_frame.h"
#include "methods/common/spherical_harmonics.h"
#include "methods/lpi/lpi.h"
#include "methods/lpi/orientation_choice.h"
#include "methods/lpi/volume_radius.h"

namespace causticbench {

using namespace lpi;

namespace {

bool has_environment_light(const Scene& scene) {
  for (const Light& light : scene.lights)
    if (is_environment_light(light.kind)) return true;
  return false;
}

// Per point of the geodesic set: whether some light needs it at some rendered frame. An environment
// light needs every point whose hat function its map lights (a non-zero weight, environment.h) in
// the object's frame at any frame; a directional or point light that does not turn there needs the
// corners its blend reads and its nearest point; one that turns needs them all.
std::vector<bool> needed_points(const Scene& scene, int object, const BoundingSphere& bounds, const std::vector<int>& frames,
                                const SphericalMesh& mesh) {
  std::vector<bool> needed(mesh.points().size(), false);
  const double cell_angle = hat_quadrature_angle(mesh);
  for (const Light& light : scene.lights) {
    if (!is_environment_light(light.kind)) continue;
    std::vector<std::pair<glm::mat3, Vec3>> done;  // (to build space, direction) already weighed
    for (int frame : frames) {
      const BuildSpaceMap map = build_space_map(scene.objects[object], frame);
      const LightFrame posed = pose_light(light, frame);
      const std::pair<glm::mat3, Vec3> pose(map.linear, posed.direction_to_light);
      if (std::find(done.begin(), done.end(), pose) != done.end()) continue;
      done.push_back(pose);
      const std::vector<glm::dvec3> weights = hat_weights(mesh, environment_quadrature(posed, cell_angle), map.linear);
      for (size_t point = 0; point < weights.size(); ++point) needed[point] = needed[point] || weights[point] != glm::dvec3(0.0);
    }
  }
  std::vector<std::vector<Vec3>> directions = object_light_directions(scene, object, bounds.center, frames);
  for (size_t l = 0; l < scene.lights.size(); ++l) {
    if (is_environment_light(scene.lights[l].kind) || directions[l].empty()) continue;
    if (!fixed_light_directions({directions[l]})) return std::vector<bool>(needed.size(), true);
    const Vec3 direction = directions[l].front();
    needed[mesh.nearest_point(direction)] = true;
    const SphericalMesh::Location location = mesh.locate(direction);
    for (int corner = 0; corner < 3; ++corner) {
      if (location.weights[corner] > 0.0f) needed[mesh.triangles()[location.triangle][corner]] = true;
    }
  }
  return needed;
}

// An environment light: the geodesic set, or with light_samples: auto the part of it the scene's
// lights reach. Symmetry cannot serve it: both symmetries turn the read point with the light's
// direction, so a map's many directions would each need the volume read at a differently turned
// point, not a weighted sum of stored volumes.
LightSampleSet environment_samples(const Scene& scene, int object, const BoundingSphere& bounds,
                                   const std::vector<int>& frames, const ParamSet& build) {
  const std::string symmetry = build.text("symmetry");
  if (symmetry != "none") {
    std::string light_name;
    for (const Light& light : scene.lights)
      if (is_environment_light(light.kind) && light_name.empty()) light_name = light.name.empty() ? "(unnamed)" : light.name;
    throw InputError(fmt::format(
        "{}: light '{}' is an environment light, and lpi with symmetry: {} {}: the light from each of the map's "
        "directions would need the stored volume read at a differently turned point, which is not a weighted sum of "
        "light samples; use symmetry: none (the geodesic set, or its part the map lights) or storage: sh",
        scene.source, light_name, symmetry,
        symmetry == "spherical" ? "stores one light sample and turns every direction onto it"
                                : "stores samples on one meridian and turns the light about the axis onto it"));
  }
  const int level = static_cast<int>(build.integer("light_subdivision"));
  const std::string at = build.text("light_sample_at");
  LightSampleSet full = geodesic_samples(level, at == "vertices" ? SampleAt::vertices : SampleAt::faces);
  const size_t total = full.directions.size();
  if (build.text("light_samples") == "all") {
    full.reason = fmt::format("light_samples: all, with an environment light: the geodesic set, subdivision {} at its "
                              "{}, {} samples, each weighted by the map's light over its hat function",
                              level, at, total);
    return full;
  }
  const std::vector<bool> needed = needed_points(scene, object, bounds, frames, *full.mesh);
  const size_t count = static_cast<size_t>(std::count(needed.begin(), needed.end(), true));
  if (count == total) {
    full.reason = fmt::format("light_samples: auto, with an environment light that lights the whole sphere of "
                              "directions in the object's frame: the geodesic set, subdivision {} at its {}, {} samples",
                              level, at, total);
    return full;
  }
  LightSampleSet part = geodesic_part(std::move(full), needed);
  part.reason = fmt::format("light_samples: auto, with an environment light: {} of the {} samples of the geodesic set "
                            "(subdivision {} at its {}), those whose hat function the map lights at some rendered frame "
                            "(and any other light's blend reads); the map leaves the other {} dark",
                            count, total, level, at, total - count);
  return part;
}

// An environment light's volumes are summed into one per frame (combine_blocks), which needs every
// light sample's values at the same points: not so with a multires tree per light sample.
void check_environment_storage(const Scene& scene, const VolumeSettings& settings) {
  if (!per_sample_trees(settings)) return;
  for (const Light& light : scene.lights)
    if (is_environment_light(light.kind))
      throw InputError(fmt::format("{}: light '{}' is an environment light, whose light samples lpi sums into one volume "
                                   "a frame, and multires_tree: per_sample gives each light sample points of its own; "
                                   "use multires_tree: shared",
                                   scene.source, light.name.empty() ? "(unnamed)" : light.name));
}

// Model only what the scene requires: a light whose direction in the object's frame never changes
// gets its one direction; otherwise the set the knobs describe.
LightSampleSet choose_samples(const Scene& scene, int object, const BoundingSphere& bounds, const std::vector<int>& frames,
                              const ParamSet& build) {
  const int level = static_cast<int>(build.integer("light_subdivision"));
  const bool at_vertices = build.text("light_sample_at") == "vertices";
  if (build.text("storage") == "sh") {
    // A fit over the sphere of light directions needs samples over all of it, even for a light that
    // never moves (light_samples and symmetry do not apply to sh).
    LightSampleSet set = geodesic_samples(level, at_vertices ? SampleAt::vertices : SampleAt::faces);
    set.reason = fmt::format("storage: sh fits spherical harmonics over the whole sphere of light directions: the "
                             "geodesic set, subdivision {} at its {}, {} samples",
                             level, build.text("light_sample_at"), set.directions.size());
    return set;
  }
  if (has_environment_light(scene)) return environment_samples(scene, object, bounds, frames, build);
  const std::vector<std::vector<Vec3>> directions = object_light_directions(scene, object, bounds.center, frames);
  const std::string symmetry = build.text("symmetry");
  if (symmetry == "spherical") {
    LightSampleSet set;
    set.kind = "spherical";
    set.reason = "symmetry: spherical: one light sample, every light direction turned onto it";
    set.directions = {Vec3(0.0f, 1.0f, 0.0f)};
    for (const auto& light : directions) {
      if (!light.empty()) {
        set.directions = {light.front()};
        break;
      }
    }
    return set;
  }
  const std::optional<std::vector<Vec3>> fixed = fixed_light_directions(directions);
  if (build.text("light_samples") == "auto" && fixed) {
    const std::vector<Vec3>& distinct = *fixed;
    LightSampleSet set;
    set.kind = "static";
    set.directions = distinct;
    set.reason = fmt::format("light_samples: auto, and no light's direction in the object's frame changes over the {} "
                             "rendered frame(s): {} light sample(s), one per direction",
                             frames.size(), distinct.size());
    return set;
  }
  const std::string why = build.text("light_samples") == "all" ? "light_samples: all"
                                                                 : "the light's direction in the object's frame changes over the rendered frames";
  if (symmetry == "axial") {
    LightSampleSet set = meridian_samples(level, Vec3(0.0f, 1.0f, 0.0f));
    set.reason = fmt::format("{}; symmetry: axial: {} samples on one meridian of the object's y axis", why,
                             set.directions.size());
    return set;
  }
  LightSampleSet set = geodesic_samples(level, at_vertices ? SampleAt::vertices : SampleAt::faces);
  set.reason = fmt::format("{}: the geodesic set, subdivision {} at its {}, {} samples", why, level,
                           build.text("light_sample_at"), set.directions.size());
  return set;
}

nlohmann::json directions_json(const std::vector<Vec3>& directions) {
  nlohmann::json list = nlohmann::json::array();
  for (const Vec3& d : directions) list.push_back({d.x, d.y, d.z});
  return list;
}

const char* kValuesFormat = "causticbench lpi values 1";

// The Vulkan kernel reads each light sample's volume with the frame's blend weights; an environment
// light's combined volume (environment.h) is evaluated on the CPU only.
void check_vulkan_lights(const Scene& scene) {
  for (const Light& light : scene.lights)
    if (is_environment_light(light.kind))
      throw InputError(fmt::format("{}: lpi backend vulkan evaluates directional and point lights; light '{}' is an "
                                   "environment light, which lpi renders with backend: cpu",
                                   scene.source, light.name));
}

// The specular objects with their bounding spheres in build space, where the probes measure from.
std::vector<std::pair<int, BoundingSphere>> build_space_bounds(const PrepareContext& context) {
  std::vector<std::pair<int, BoundingSphere>> objects;
  for (int object : context.rest.specular_objects()) {
    const Scene alone = build_space_scene(context.scene, object);
    objects.emplace_back(object, SceneFrame(alone, 0.0).bounds[0]);
  }
  return objects;
}

// orientation: auto takes what the scene's receivers need (orientation_choice.h); returns why.
std::string resolve_orientation(const PrepareContext& context, VolumeSettings& settings) {
  if (!settings.orientation_auto)
    return fmt::format("orientation: {} (set)", settings.orientation == Orientation::paper ? "paper" : "vector");
  const bool one_cell = ((settings.storage == StorageKind::grid || settings.storage == StorageKind::sh) &&
                         settings.grid_resolution == 1) ||
                        (settings.storage == StorageKind::multires && settings.multires_depth == 0);
  const OrientationChoice choice = choose_orientation(context, build_space_bounds(context), one_cell);
  settings.orientation = choice.orientation;
  return choice.reason;
}

}  // namespace

void LpiMethod::plan(const PrepareContext& context, const ParamSet& build) {
  settings_ = volume_settings(build);
  orientation_reason_ = resolve_orientation(context, settings_);
  backend_ = build.text("backend");
  if (backend_ == "vulkan") {
    check_vulkan_supports(settings_);
    check_vulkan_lights(context.scene);
  }
  check_environment_storage(context.scene, settings_);
  scene_ = &context.scene;
  objects_.clear();
  frame_.clear();
  environment_.clear();
  for (int object : context.rest.specular_objects()) {
    ObjectVolumes volumes;
    volumes.object = object;
    volumes.name = context.scene.objects[object].name;
    const Scene alone = build_space_scene(context.scene, object);
    const SceneFrame frame(alone, 0.0);
    volumes.bounds = frame.bounds[0];
    volumes.samples = choose_samples(context.scene, object, volumes.bounds, context.frames, build);
    if (settings_.storage == StorageKind::sh &&
        volumes.samples.directions.size() < static_cast<size_t>(coefficient_count(settings_.sh_order + 1))) {
      throw InputError(fmt::format("lpi: sh_order {} has {} coefficients a cell, more than the {} light samples of "
                                   "light_subdivision {} can determine; raise light_subdivision or lower sh_order",
                                   settings_.sh_order, coefficient_count(settings_.sh_order + 1),
                                   volumes.samples.directions.size(), build.integer("light_subdivision")));
    }
    const VolumeRadius radius = choose_volume_radius(context, object, volumes.bounds, settings_);
    volumes.volume_radius = radius.radii;
    volumes.volume_radius_reason = radius.reason;
    if (radius.capped && radius.lost_at_cap > kLostFluxWarning)
      fmt::print(stderr, "warning: lpi: object '{}': {}; raise the storage's resolution, or set volume_radius\n",
                 volumes.name, radius.reason);
    volumes.layout = make_layout(settings_, volumes.bounds, radius.radii);
    objects_.push_back(std::move(volumes));
  }
}

// Per specular object: its shape, material and scale at frame 0 (not where it stands or how it is
// turned: the build is in the object's own frame), and the light directions its set holds.
std::optional<nlohmann::json> LpiMethod::build_dependencies(const PrepareContext& context, const ParamSet& build) const {
  // Refused before the cache is looked at: a combination the kernel does not evaluate.
  if (build.text("backend") == "vulkan") {
    check_vulkan_supports(volume_settings(build));
    check_vulkan_lights(context.scene);
  }
  check_environment_storage(context.scene, volume_settings(build));
  nlohmann::json objects = nlohmann::json::array();
  for (int object : context.rest.specular_objects()) {
    const SceneObject& source = context.scene.objects[object];
    const Scene alone = build_space_scene(context.scene, object);
    const SceneFrame frame(alone, 0.0);
    const LightSampleSet set = choose_samples(context.scene, object, frame.bounds[0], context.frames, build);
    const glm::dvec3 scale = source.transform.scale.at(0.0);
    nlohmann::json samples = {{"kind", set.kind}};
    if (set.kind == "static" || set.kind == "spherical") samples["directions"] = directions_json(set.directions);
    if (set.kind == "environment") samples["points"] = set.mesh_points;
    nlohmann::json entry = {{"shape", shape_json(source.shape)},
                            {"material", material_json(source.material)},
                            {"scale", {scale.x, scale.y, scale.z}},
                            {"light_samples", samples}};
    // auto: the ball the probes chose (it depends on the receivers, which the build otherwise does not).
    if (build.is_auto("volume_radius"))
      entry["volume_radius"] = choose_volume_radius(context, object, frame.bounds[0], volume_settings(build)).radii;
    objects.push_back(std::move(entry));
  }
  // backend: cpu leaves the keys of builds stored before the knob as they were; every other build knob,
  // vulkan included, names a build of its own (the suite's rule: tests/test_conformance.cpp).
  nlohmann::json dependencies{{"objects", objects}, {"build", build.key_json(static_info().params)}};
  // auto: the orientation the probes chose (it depends on the receivers too).
  VolumeSettings settings = volume_settings(build);
  if (settings.orientation_auto) {
    resolve_orientation(context, settings);
    dependencies["orientation"] = settings.orientation == Orientation::paper ? "paper" : "vector";
  }
  return dependencies;
}

// The build's peak (precompute.cpp, shoot_light_samples), per specular object, V = points x channels
// deposited, S light samples: every sample's values as floats (4 V S), eight chunk sums of floats and
// one of doubles (40 V), then the stored copy at `precision` (p V S) beside the floats. multires: the
// tree's collapse holds per leaf a vector of S x channels doubles and the leaves' floats, bounded by
// the worst case of every finest cell a leaf; sh: the fitted coefficients as floats beside the
// samples. vulkan: the device's copy of the stored values (host memory under lavapipe). Objects are
// summed although their transients do not overlap: an upper bound, within about 1.3x for one object.
std::vector<MemoryTerm> LpiMethod::knob_memory(const PrepareContext& context, const ParamSet& knobs) const {
  VolumeSettings settings = volume_settings(knobs);
  resolve_orientation(context, settings);
  std::vector<MemoryTerm> terms;
  for (int object : context.rest.specular_objects()) {
    const Scene alone = build_space_scene(context.scene, object);
    const SceneFrame frame(alone, 0.0);
    const LightSampleSet set = choose_samples(context.scene, object, frame.bounds[0], context.frames, knobs);
    const double samples = static_cast<double>(set.directions.size());
    const double channels = channel_count(settings.orientation);
    const double precision = static_cast<double>(precision_bytes(settings.precision));
    MemoryTerm term;
    double points = 0.0, stored_blocks = samples, extra = 0.0;
    std::string volume;
    if (settings.storage == StorageKind::grid || settings.storage == StorageKind::sh) {
      points = std::pow(static_cast<double>(settings.grid_resolution), 3.0);
      volume = fmt::format("{}^3 cells", settings.grid_resolution);
      term.knobs = {"grid_resolution"};
    } else if (settings.storage == StorageKind::shells) {
      points = settings.shell_count * (10.0 * std::pow(4.0, settings.shell_subdivision) + 2.0);
      volume = fmt::format("{} shells x {} vertices", settings.shell_count,
                           10.0 * std::pow(4.0, settings.shell_subdivision) + 2.0);
      term.knobs = {"shell_count", "shell_subdivision"};
    } else {
      points = std::pow(8.0, settings.multires_depth);
      volume = fmt::format("{}^3 finest cells", 1 << settings.multires_depth);
      term.knobs = {"multires_depth"};
      extra = points * (samples * channels * 8.0 + 48.0 + samples * channels * 4.0);
    }
    if (settings.storage == StorageKind::sh) {
      stored_blocks = coefficient_count(settings.sh_order + 1);
      extra = points * channels * 4.0 * stored_blocks;
      term.knobs.push_back("sh_order");
    }
    if (set.kind != "static" && set.kind != "spherical") term.knobs.push_back("light_subdivision");
    const double values = points * channels;
    const double stored = values * stored_blocks * precision * (knobs.text("backend") == "vulkan" ? 2.0 : 1.0);
    term.bytes = values * (4.0 * samples + 40.0) + extra + stored;
    term.formula = fmt::format("object '{}': {} x {:.0f} channels x ({:.0f} bytes while shooting {:.0f} light sample{}) "
                               "+ {:.0f} MiB stored{}",
                               context.scene.objects[object].name, volume, channels, 4.0 * samples + 40.0, samples, samples == 1.0 ? "" : "s",
                               stored / 1048576.0, extra > 0.0 ? fmt::format(" + {:.0f} MiB while collapsing or fitting", extra / 1048576.0) : "");
    terms.push_back(std::move(term));
  }
  return terms;
}

// One file per object: a header line, then the stored values' raw bytes and their uint8 scales.
void LpiMethod::save_build(const std::string& folder) const {
  nlohmann::json meta = nlohmann::json::array();
  for (size_t i = 0; i < objects_.size(); ++i) {
    const ObjectVolumes& object = objects_[i];
    const std::string name = fmt::format("object_{}.bin", i);
    write_stream_atomically((std::filesystem::path(folder) / name).string(), [&](std::ostream& stream) {
    const uint64_t header[3] = {object.values.bytes().size(), object.values.scales().size(), object.values.points()};
    stream.write(kValuesFormat, static_cast<std::streamsize>(std::strlen(kValuesFormat) + 1));
    stream.write(reinterpret_cast<const char*>(header), sizeof(header));
    stream.write(reinterpret_cast<const char*>(object.values.bytes().data()),
                 static_cast<std::streamsize>(object.values.bytes().size()));
    stream.write(reinterpret_cast<const char*>(object.values.scales().data()),
                 static_cast<std::streamsize>(object.values.scales().size() * sizeof(float)));
    // An adaptive layout's structure (the multires tree or trees) after the values: its words' count, then them.
    const std::vector<uint32_t> structure = object.layout->structure();
    if (object.layout->adaptive()) {
      const uint64_t words = structure.size();
      stream.write(reinterpret_cast<const char*>(&words), sizeof(words));
      stream.write(reinterpret_cast<const char*>(structure.data()), static_cast<std::streamsize>(words * sizeof(uint32_t)));
    }
    });
    meta.push_back({{"file", name},
                    {"object", object.name},
                    {"shoot_seconds", object.shoot_seconds},
                    {"emitted", object.stats.emitted},
                    {"deposited", object.stats.deposited},
                    {"rays", object.stats.rays}});
  }
  write_text_atomically((std::filesystem::path(folder) / "volumes.json").string(), meta.dump(2) + "\n");
}

void LpiMethod::load_build(const PrepareContext& context, const ParamSet& build, const std::string& folder) {
  plan(context, build);
  std::ifstream meta_stream(std::filesystem::path(folder) / "volumes.json");
  const nlohmann::json meta = nlohmann::json::parse(meta_stream, nullptr, false);
  if (meta.is_discarded() || !meta.is_array() || meta.size() != objects_.size()) {
    throw std::runtime_error(folder + "/volumes.json: unreadable or not one entry per specular object");
  }
  for (size_t i = 0; i < objects_.size(); ++i) {
    ObjectVolumes& object = objects_[i];
    const std::string path = (std::filesystem::path(folder) / fmt::format("object_{}.bin", i)).string();
    std::ifstream stream(path, std::ios::binary);
    std::string format(std::strlen(kValuesFormat) + 1, '\0');
    stream.read(format.data(), static_cast<std::streamsize>(format.size()));
    uint64_t header[3] = {};
    stream.read(reinterpret_cast<char*>(header), sizeof(header));
    const size_t channels = static_cast<size_t>(channel_count(settings_.orientation));
    const size_t blocks = stored_blocks(settings_, object);
    const bool adaptive = object.layout->adaptive();
    // An adaptive layout's point count comes with its structure, after the values.
    const bool points_match = adaptive || header[2] == object.layout->points();
    if (!stream || format != std::string(kValuesFormat, format.size()) || !points_match || header[1] != blocks ||
        header[0] != (per_sample_trees(settings_) ? 1 : blocks) * header[2] * channels * precision_bytes(settings_.precision)) {
      throw std::runtime_error(path + ": not the values of this build");
    }
    std::vector<uint8_t> bytes(header[0]);
    std::vector<float> scales(header[1]);
    stream.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    stream.read(reinterpret_cast<char*>(scales.data()), static_cast<std::streamsize>(scales.size() * sizeof(float)));
    if (adaptive) {
      uint64_t words = 0;
      stream.read(reinterpret_cast<char*>(&words), sizeof(words));
      if (!stream || words > (uint64_t{1} << 31)) throw std::runtime_error(path + ": truncated");
      std::vector<uint32_t> structure(words);
      stream.read(reinterpret_cast<char*>(structure.data()), static_cast<std::streamsize>(words * sizeof(uint32_t)));
      if (!stream) throw std::runtime_error(path + ": truncated");
      object.layout->restore(std::move(structure));
      if (object.layout->points() != header[2]) throw std::runtime_error(path + ": not the values of this build");
    }
    if (!stream) throw std::runtime_error(path + ": truncated");
    object.harmonic = settings_.storage == StorageKind::sh;
    const bool signed_values = settings_.orientation == Orientation::vector || object.harmonic;
    const auto* tree = dynamic_cast<const MultiresLayout*>(object.layout.get());
    if (tree && tree->per_sample() && tree->sample_trees() != blocks) throw std::runtime_error(path + ": not the values of this build");
    object.values = tree && tree->per_sample()
                        ? StoredValues::from_raw(settings_.precision, static_cast<int>(channels), signed_values,
                                                 tree->block_points(blocks), std::move(bytes), std::move(scales))
                        : StoredValues::from_raw(settings_.precision, static_cast<int>(channels), signed_values,
                                                 object.layout->points(), std::move(bytes), std::move(scales));
    object.shoot_seconds = meta[i].value("shoot_seconds", 0.0);
    object.stats = PhotonStats{meta[i].value("emitted", uint64_t{0}), meta[i].value("deposited", uint64_t{0}),
                               meta[i].value("rays", uint64_t{0})};
  }
  start_backend();
}

}  // namespace causticbench
