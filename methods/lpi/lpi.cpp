#include "methods/lpi/lpi.h"

#include <chrono>

#include <fmt/format.h>

#include "core/errors.h"
#include "core/parallel.h"
#include "core/progress.h"
#include "methods/common/gpu_arrays.h"
#include "methods/lpi/environment.h"
#include "methods/lpi/gpu_frame.h"
#include "methods/lpi/lookup.h"
#include "methods/lpi/multires_layout.h"
#include "methods/lpi/vulkan_lpi.h"
#include "methods/lpi/spherical_harmonics.h"

namespace causticbench {

using namespace lpi;

namespace {

// The paper's orientation stores irradiance across the direction from the object's centre to each
// sample point. A volume of one cell has its only sample at the centre, where that direction does not
// exist: every value would be 0 and the image black, silently (found by study_extremes_knobs.yaml).
std::string one_cell_paper_problem(bool one_cell, const std::string& cells, const std::string& more, const ParamSet& knobs) {
  if (!one_cell || knobs.text("orientation") != "paper") return "";
  return fmt::format("{} gives one cell, centred on the object, and orientation 'paper' needs the direction from the "
                     "object's centre to each sample point, which that cell lacks (its value would be 0): use {} or "
                     "orientation: vector",
                     cells, more);
}

std::string grid_one_cell_problem(const ParamSet& knobs) {
  return one_cell_paper_problem(knobs.integer("grid_resolution") == 1, "grid_resolution 1", "grid_resolution 2 or more", knobs);
}

std::string multires_one_cell_problem(const ParamSet& knobs) {
  return one_cell_paper_problem(knobs.integer("multires_depth") == 0, "multires_depth 0", "multires_depth 1 or more", knobs);
}

// Spherical harmonics over the light directions are fitted to the geodesic set's samples: (order + 1)^2
// coefficients need at least as many samples.
std::string sh_samples_problem(const ParamSet& knobs) {
  const int64_t order = knobs.integer("sh_order"), subdivision = knobs.integer("light_subdivision");
  const int64_t power = int64_t{1} << (2 * subdivision);
  const int64_t samples = knobs.text("light_sample_at") == "faces" ? 20 * power : 10 * power + 2;
  const int64_t coefficients = (order + 1) * (order + 1);
  if (coefficients <= samples) return "";
  return fmt::format("sh_order {} has {} coefficients a cell, more than the {} light samples of light_subdivision {} "
                     "can determine; raise light_subdivision or lower sh_order",
                     order, coefficients, samples, subdivision);
}

}  // namespace

LpiMethod::LpiMethod() = default;
LpiMethod::~LpiMethod() = default;

const MethodInfo& LpiMethod::static_info() {
  static const MethodInfo info = [] {
    MethodInfo m;
    m.name = "lpi";
    m.paper = "C. Wyman, C. Hansen, P. Shirley, \"Interactive Raytraced Caustics\", Univ. of Utah UUCS-03-009, 2003 "
              "(local precomputed irradiance)";
    m.summary = "Precomputes each specular object's caustic irradiance in a volume around it (a grid, concentric "
                "geodesic shells or an adaptive octree; or per cell spherical harmonics over light directions) for a "
                "set of light directions, by photon tracks through the object alone; per frame "
                "it turns the light into the object's frame and looks the caustic up, blending neighbouring light samples "
                "(an environment map: every light sample, weighted by the map's light around it).";
    const std::vector<std::string> grid_or_sh = {"grid", "sh"}, shells = {"shells"}, multires = {"multires"}, sh = {"sh"};
    // sh fits over the whole sphere of light directions and reads no light sample by itself.
    const std::vector<std::string> sampled = {"grid", "shells", "multires"};
    m.params = {
        ParamSpec::choice("storage", "grid", {"grid", "shells", "multires", "sh"},
                          "how the volume is sampled: a uniform grid of cells, concentric shells sampled at geodesic "
                          "vertices (Section 4.2), an octree refined where the caustic varies, or per grid cell "
                          "spherical harmonics over light directions (Section 4.3)",
                          ParamPhase::build),
        ParamSpec::integer("grid_resolution", 64, 1, 512,
                           "cells along each axis of the grid over the sampled ball (sh: each holds its coefficients)",
                           ParamPhase::build)
            .only_when("storage", grid_or_sh),
        ParamSpec::integer("shell_count", 12, 1, 256, "concentric shells from the centre to volume_radius", ParamPhase::build)
            .only_when("storage", shells),
        ParamSpec::integer("shell_subdivision", 4, 0, 7,
                           "subdivisions of the icosahedron whose 10 4^s + 2 vertices sample each shell", ParamPhase::build)
            .only_when("storage", shells),
        ParamSpec::choice("shell_spacing", "uniform", {"uniform", "quadratic"},
                          "radii of the shells: uniform, or quadratic (r_k = R ((k + 1) / K)^2, denser near the object)",
                          ParamPhase::build)
            .only_when("storage", shells),
        ParamSpec::integer("multires_depth", 6, 0, 9,
                           "levels of the multires octree below its root: the finest cells are those of a 2^depth grid",
                           ParamPhase::build)
            .only_when("storage", multires),
        ParamSpec::real("error_threshold", 0.01, 0.0, 1.0,
                        "a multires subtree becomes one leaf, its mean, when every finest cell in it lies within "
                        "error_threshold x the light sample's largest value of that mean (every channel, and every light "
                        "sample the tree serves)",
                        ParamPhase::build)
            .only_when("storage", multires),
        // Added after experiments shipped: at shared it stays out of their run keys and build-cache keys,
        // so stored shared trees keep theirs; per_sample names builds of its own.
        ParamSpec::choice("multires_tree", "shared", {"shared", "per_sample"},
                          "shared: one octree for all light samples, refined where any sample's caustic varies (one "
                          "descent a receiver point); per_sample: an octree per light sample, refined only where its "
                          "own caustic varies (fewer values, its own tree words, a descent per read)",
                          ParamPhase::build)
            .only_when("storage", multires)
            .unkeyed_at_default(),
        ParamSpec::integer("sh_order", 4, 0, 9,
                           "highest degree of the spherical harmonics over light directions, (order + 1)^2 coefficients "
                           "a cell and channel (4: the paper's 5th order read as 5 bands, Fig. 9)",
                           ParamPhase::build)
            .only_when("storage", sh),
        ParamSpec::choice("precision", "float32", {"uint8", "float16", "float32"},
                          "stored value type; uint8 scales each light sample's values to 0..255 (the paper stored 3 bytes a colour)",
                          ParamPhase::build),
        ParamSpec::choice("orientation", "paper", {"paper", "vector"},
                          "paper: irradiance on the surface facing the object's centre, corrected by the cosine to the "
                          "receiver's normal (Section 3.2); vector: the vector irradiance, shaded max(0, n . E)",
                          ParamPhase::build),
        ParamSpec::real("volume_radius", 3.0, 0.01, 1000.0, "radius of the sampled ball, in bounding radii of the object",
                        ParamPhase::build),
        ParamSpec::integer("photons_per_sample", 1000000, 1, 4e9, "photons shot at the object per light sample",
                           ParamPhase::build),
        ParamSpec::integer("seed", 1, 0, 4e9, "seed of the photon paths", ParamPhase::build),
        ParamSpec::choice("light_samples", "auto", {"auto", "all"},
                          "auto: when no light's direction in an object's frame changes over the rendered frames, just "
                          "those directions; with an environment light, the geodesic samples its map lights; otherwise "
                          "(and with all) the geodesic set",
                          ParamPhase::build)
            .only_when("storage", sampled),
        ParamSpec::integer("light_subdivision", 2, 0, 6,
                           "subdivisions of the icosahedron of light directions (2: 162 vertices, as for the bunny)",
                           ParamPhase::build),
        ParamSpec::choice("light_sample_at", "vertices", {"vertices", "faces"},
                          "light samples at the geodesic's vertices (10 4^s + 2) or face centres (20 4^s)", ParamPhase::build),
        ParamSpec::choice("symmetry", "none", {"none", "axial", "spherical"},
                          "axial: samples on one meridian of the object's local y axis, the lookup turns the light about "
                          "it; spherical: one sample, every direction turned onto it",
                          ParamPhase::build)
            .only_when("storage", sampled),
        ParamSpec::choice("blend", "barycentric", {"nearest", "barycentric", "aligned"},
                          "nearest light sample (pops), barycentric blend of three (ghosts), or aligned: each of the "
                          "three read at the point turned by the angle between it and the light (Section 5.2)",
                          ParamPhase::frame)
            .only_when("storage", sampled),
        // Added after experiments shipped: at combined it stays out of their run keys.
        ParamSpec::choice("environment_clamp", "combined", {"combined", "per_sample"},
                          "environment lights, orientation vector: combined: the light samples' volumes summed into one "
                          "and shaded max(0, n . E) once; per_sample: each sample shaded max(0, n . E_s), then weighted "
                          "and summed (every sample read a pixel)",
                          ParamPhase::frame)
            .only_when("storage", sampled)
            .unkeyed_at_default(),
        ParamSpec::choice("outside", "clamp", {"clamp", "fade", "zero"},
                          "beyond the sampled ball: the value on its surface (clamp), that times (R / d)^2 (fade), or none",
                          ParamPhase::render),
        // Added after experiments shipped: at cpu it stays out of their run keys.
        ParamSpec::choice("backend", "cpu", {"cpu", "vulkan"},
                          "cpu (multithreaded) or vulkan (compute shader, storage grid and shells; lavapipe without a GPU)",
                          ParamPhase::build)
            .unkeyed_at_default(),
    };
    Capabilities& c = m.capabilities;
    c.reflection = c.refraction = true;
    c.directional_light = c.environment_light = true;
    c.moving_light = c.moving_objects = true;
    c.non_lambertian_receivers = true;
    c.notes = {
        {"multiple_bounces", "any number within one object (glass in and out, a ring's self-reflections); none between "
                             "objects: each object's caustic is precomputed alone"},
        {"point_light", "taken as a directional light from the object's centre, with the irradiance there"},
        {"environment_light", "beyond the paper: the light samples' volumes weighted by the map's light over each "
                              "sample's barycentric hat function (storage: sh: a dot product with the map's projection, "
                              "as precomputed radiance transfer); not with symmetry axial or spherical"},
        {"moving_light", "light samples over the directions the light takes in the object's frame, blended per frame"},
        {"moving_objects", "the caustic moves and turns with its object; a changing scale is not followed"},
        {"occlusion", "the caustic reaches receivers behind other objects"},
        {"non_lambertian_receivers", "E_c is irradiance, whatever the receiver's BRDF"},
    };
    m.frame_dump = true;
    m.knob_rules = {{{"grid_resolution", "orientation"}, grid_one_cell_problem},
                    {{"multires_depth", "orientation"}, multires_one_cell_problem},
                    {{"sh_order", "light_subdivision", "light_sample_at"}, sh_samples_problem}};
    m.quick_knobs = {"photons_per_sample=20000", "light_subdivision=0"};
    m.counters = {counter_quantity("light_samples", "samples", "light directions precomputed (over all objects)"),
                  counter_quantity("photons_emitted", "photons", "photons shot over all light samples and objects"),
                  counter_quantity("shoot_seconds_per_light_sample", "s", "precomputation time per light sample",
                                   QuantityKind::timing),
                  counter_quantity("bytes_per_light_sample", "bytes", "stored irradiance per light sample",
                                   QuantityKind::size),
                  counter_quantity("volume_reads_per_frame", "reads",
                                   "interpolated volume reads of the last frame rendered: receiver points x light "
                                   "samples read, over objects and lights (divided by render_ms: the lookup rate)")};
    return m;
  }();
  return info;
}

VolumeSettings lpi::volume_settings(const ParamSet& build) {
  VolumeSettings settings;
  const std::string storage = build.text("storage");
  settings.storage = storage == "grid"       ? StorageKind::grid
                     : storage == "shells"   ? StorageKind::shells
                     : storage == "multires" ? StorageKind::multires
                                             : StorageKind::sh;
  if (settings.storage == StorageKind::grid || settings.storage == StorageKind::sh) {
    settings.grid_resolution = static_cast<int>(build.integer("grid_resolution"));
  }
  if (settings.storage == StorageKind::sh) settings.sh_order = static_cast<int>(build.integer("sh_order"));
  if (settings.storage == StorageKind::multires) {
    settings.multires_depth = static_cast<int>(build.integer("multires_depth"));
    settings.error_threshold = build.real("error_threshold");
    settings.multires_tree = build.text("multires_tree") == "per_sample" ? MultiresTree::per_sample : MultiresTree::shared;
  }
  if (settings.storage == StorageKind::shells) {
    settings.shell_count = static_cast<int>(build.integer("shell_count"));
    settings.shell_subdivision = static_cast<int>(build.integer("shell_subdivision"));
    settings.shell_spacing = build.text("shell_spacing") == "uniform" ? 0 : 1;
  }
  settings.precision = parse_precision(build.text("precision"));
  settings.orientation = build.text("orientation") == "paper" ? Orientation::paper : Orientation::vector;
  // The knob rules (static_info) refuse these before any work; a caller that bypassed them still stops here.
  const std::string one_cell = build.has("grid_resolution")  ? grid_one_cell_problem(build)
                               : build.has("multires_depth") ? multires_one_cell_problem(build)
                                                             : "";
  if (!one_cell.empty()) throw InputError("lpi: " + one_cell);
  settings.volume_radius = build.real("volume_radius");
  settings.photons_per_sample = static_cast<uint64_t>(build.integer("photons_per_sample"));
  settings.seed = static_cast<uint64_t>(build.integer("seed"));
  return settings;
}

void LpiMethod::check_scene(const Scene& scene) const {
  if (!scene.has_specular_object()) {
    throw InputError(fmt::format("{}: lpi precomputes the caustics of specular objects, and the scene has none",
                                 scene.source));
  }
}

void LpiMethod::prepare(const PrepareContext& context, const ParamSet& build) {
  plan(context, build);
  size_t total = 0;
  for (const ObjectVolumes& object : objects_) total += object.samples.directions.size();
  Progress progress("lpi light samples", static_cast<double>(total));
  size_t done_before = 0;
  for (ObjectVolumes& object : objects_) {
    const Scene alone = build_space_scene(context.scene, object.object);
    shoot_light_samples(alone, settings_, object, [&](size_t done, size_t) {
      progress.update(static_cast<double>(done_before + done), object.name);
    });
    done_before += object.samples.directions.size();
  }
  progress.finish();
  start_backend();
}

void LpiMethod::start_backend() {
  gpu_frame_ = LpiFrameData{};
  if (backend_ != "vulkan") {
    vulkan_.reset();
    return;
  }
  if (!gpu_context_) gpu_context_ = std::make_unique<gpu::Context>();
  if (!vulkan_) vulkan_ = std::make_unique<VulkanLpi>(*gpu_context_);
  fill_volume_data(settings_, objects_, gpu_frame_);
  vulkan_->upload_volumes(gpu_frame_);
}

void LpiMethod::update(const FrameContext& frame, const ParamSet& frame_knobs) {
  const bool harmonic = settings_.storage == StorageKind::sh;
  const std::string blend_name = harmonic ? "" : frame_knobs.text("blend");
  const Blend blend = blend_name == "nearest" ? Blend::nearest : blend_name == "barycentric" ? Blend::barycentric : Blend::aligned;
  frame_.assign(objects_.size(), lpi::ObjectFrame{});
  environment_.resize(objects_.size());
  for (size_t i = 0; i < objects_.size(); ++i) {
    const ObjectVolumes& object = objects_[i];
    lpi::ObjectFrame& view = frame_[i];
    view.map = build_space_map(scene_->objects[object.object], frame.frame.frame);
    update_environment(i, frame.frame.lights, view.map, !harmonic && frame_knobs.text("environment_clamp") == "per_sample");
    for (const LightFrame& light : frame.frame.lights) {
      if (is_environment_light(light.kind)) continue;  // in environment_[i]
      const ObjectLight seen = object_light(view.map, light, object.bounds.center);
      if (!seen.valid) continue;
      lpi::LightView light_view;
      light_view.irradiance = seen.irradiance;
      const Vec3 direction = seen.direction;
      if (harmonic) {
        // The coefficients' weights: the basis at the light's direction.
        light_view.harmonics.resize(object.values.light_samples());
        evaluate(settings_.sh_order + 1, direction, light_view.harmonics.data());
      } else {
        light_view.reads = light_reads(object.samples, direction, blend);
      }
      view.lights.push_back(light_view);
    }
  }
}

// An environment light's weights (environment.h) depend on the object's turn and the light's pose
// only: when neither changed since the last frame, the combined volume serves again.
void LpiMethod::update_environment(size_t object_index, const std::vector<LightFrame>& lights, const BuildSpaceMap& map,
                                   bool per_sample) {
  const ObjectVolumes& object = objects_[object_index];
  EnvironmentState& state = environment_[object_index];
  std::vector<Vec3> pose = {map.linear[0], map.linear[1], map.linear[2]};
  for (const LightFrame& light : lights)
    if (is_environment_light(light.kind)) pose.push_back(light.direction_to_light);
  if (pose.size() == 3) {
    state = EnvironmentState{};
    return;
  }
  if (state.active && state.pose == pose && state.per_sample == per_sample) return;
  const auto start = std::chrono::steady_clock::now();
  const bool harmonic = settings_.storage == StorageKind::sh;
  const int bands = settings_.sh_order + 1;
  const double cell_angle = harmonic ? harmonic_quadrature_angle(bands) : hat_quadrature_angle(*object.samples.mesh);
  std::vector<glm::dvec3> block_weights(object.values.light_samples(), glm::dvec3(0.0));
  state.quadrature_points = 0;
  state.outside_set = glm::dvec3(0.0);
  for (const LightFrame& light : lights) {
    if (!is_environment_light(light.kind)) continue;
    const EnvironmentQuadrature quadrature = environment_quadrature(light, cell_angle);
    state.quadrature_points += quadrature.directions.size();
    if (harmonic) {
      const std::vector<glm::dvec3> weights = harmonic_weights(bands, quadrature, map.linear);
      for (size_t k = 0; k < weights.size(); ++k) block_weights[k] += weights[k];
      continue;
    }
    const std::vector<glm::dvec3> weights = hat_weights(*object.samples.mesh, quadrature, map.linear);
    for (uint32_t point = 0; point < weights.size(); ++point) {
      const int32_t sample = object.samples.sample_of(point);
      // The plan holds every point the rendered frames light; a frame it was not told of may not.
      if (sample >= 0) {
        block_weights[static_cast<size_t>(sample)] += weights[point];
      } else {
        state.outside_set += weights[point];
      }
    }
  }
  // per_sample: render() reads each block with its weight and clamps it alone; nothing to combine.
  state.per_sample = per_sample;
  state.values = per_sample ? StoredValues{} : combine_blocks(object.values, block_weights);
  state.weights = std::move(block_weights);
  state.pose = std::move(pose);
  state.active = true;
  state.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

namespace {

Outside outside_mode(const ParamSet& render) {
  const std::string& outside = render.text("outside");
  return outside == "clamp" ? Outside::clamp : outside == "fade" ? Outside::fade : Outside::zero;
}

}  // namespace

// One light of irradiance W_s reading block s alone, for every block the map lights.
std::vector<LightView> LpiMethod::environment_reads(const EnvironmentState& state) {
  std::vector<LightView> views;
  for (size_t block = 0; block < state.weights.size(); ++block) {
    if (state.weights[block] == glm::dvec3(0.0)) continue;
    LightView view;
    view.irradiance = Color(state.weights[block]);
    view.reads.count = 1;
    view.reads.reads[0] = SampleRead{static_cast<uint32_t>(block), 1.0f, false, glm::mat3(1.0f)};
    views.push_back(view);
  }
  return views;
}

Image LpiMethod::render(const GBuffer& gbuffer, const ParamSet& render) {
  Image result(gbuffer.width, gbuffer.height, 3);
  // environment_clamp: per_sample: every lit sample as a light of its own, so that each is clamped alone.
  std::vector<std::vector<LightView>> per_sample(objects_.size());
  for (size_t i = 0; i < objects_.size(); ++i)
    if (environment_[i].active && environment_[i].per_sample) per_sample[i] = environment_reads(environment_[i]);
  // Counted from the frame's plan, not in the per-pixel loop: each receiver point reads each light's
  // samples (one coefficient stencil for storage: sh) of every object.
  size_t reads_per_point = 0;
  for (size_t i = 0; i < frame_.size(); ++i) {
    for (const lpi::LightView& light : frame_[i].lights) reads_per_point += light.harmonics.empty() ? light.reads.count : 1;
    if (environment_[i].active) reads_per_point += environment_[i].per_sample ? per_sample[i].size() : 1;
  }
  volume_reads_ = static_cast<double>(gbuffer.receiver_count()) * static_cast<double>(reads_per_point);
  const Outside mode = outside_mode(render);
  if (vulkan_) {
    fill_frame_lights(frame_, mode, gpu_frame_);
    fill_receivers(gbuffer, gpu_frame_);
    vulkan_->upload_frame(gpu_frame_);
    return image_of_rgba(gbuffer.width, gbuffer.height, vulkan_->render(gpu_frame_, gpu_render_ms_));
  }
  // The environment lights: one read of the combined volume (environment_), whose weights carry their colour.
  LightView environment_light;
  environment_light.irradiance = Color(1.0f);
  environment_light.reads.count = 1;
  environment_light.reads.reads[0] = SampleRead{0, 1.0f, false, glm::mat3(1.0f)};
  parallel_blocks(gbuffer.pixel_count(), 1024, [&](size_t begin, size_t end, size_t) {
    for (size_t i = 0; i < objects_.size(); ++i) {
      const VolumeLayout& layout = *objects_[i].layout;
      // The concrete layout, so that its stencil inlines into the per-pixel loop.
      auto add = [&](const ObjectView& view) {
        if (const auto* grid = dynamic_cast<const GridLayout*>(&layout)) {
          add_object_caustic(*grid, view, gbuffer, begin, end, result);
        } else if (const auto* tree = dynamic_cast<const MultiresLayout*>(&layout)) {
          add_object_caustic(*tree, view, gbuffer, begin, end, result);
        } else {
          add_object_caustic(static_cast<const ShellLayout&>(layout), view, gbuffer, begin, end, result);
        }
      };
      add(ObjectView{objects_[i].values, frame_[i].map, frame_[i].lights.data(), frame_[i].lights.size(), mode});
      if (environment_[i].active && environment_[i].per_sample) {
        add(ObjectView{objects_[i].values, frame_[i].map, per_sample[i].data(), per_sample[i].size(), mode});
      } else if (environment_[i].active) {
        add(ObjectView{environment_[i].values, frame_[i].map, &environment_light, 1, mode});
      }
    }
  });
  return result;
}

size_t LpiMethod::memory_bytes() const {
  size_t bytes = 0;
  for (const ObjectVolumes& object : objects_) {
    bytes += object.values.memory_bytes() + object.layout->memory_bytes() + object.layout->index_bytes();
    if (object.samples.mesh) bytes += object.samples.mesh->memory_bytes();
  }
  for (const EnvironmentState& state : environment_) bytes += state.values.memory_bytes();
  return bytes;
}

Counters LpiMethod::counters() const {
  double samples = 0.0, photons = 0.0, seconds = 0.0, bytes_per_sample = 0.0;
  for (const ObjectVolumes& object : objects_) {
    samples += static_cast<double>(object.samples.directions.size());
    photons += static_cast<double>(object.stats.emitted);
    seconds += object.shoot_seconds;
    bytes_per_sample += lpi::bytes_per_light_sample(object);
  }
  return {{"light_samples", samples},
          {"photons_emitted", photons},
          {"shoot_seconds_per_light_sample", samples > 0.0 ? seconds / samples : 0.0},
          {"bytes_per_light_sample", bytes_per_sample},
          {"volume_reads_per_frame", volume_reads_}};
}

nlohmann::json LpiMethod::record() const {
  nlohmann::json objects = nlohmann::json::array();
  for (const ObjectVolumes& object : objects_) {
    nlohmann::json entry = {{"object", object.name},
                            {"light_sample_set", object.samples.kind},
                            {"why", object.samples.reason},
                            {"light_samples", object.samples.directions.size()},
                            {"sample_points", object.layout->points()},
                            {"bytes_per_light_sample", lpi::bytes_per_light_sample(object)},
                            {"memory_bytes", object.values.memory_bytes() + object.layout->memory_bytes() +
                                                 object.layout->index_bytes()},
                            {"volume_radius", object.layout->radius()},
                            {"shoot_seconds", object.shoot_seconds}};
    if (const auto* tree = dynamic_cast<const MultiresLayout*>(object.layout.get())) {
      entry["tree_nodes"] = tree->nodes();
      entry["finest_cells"] = tree->deposit_points();
      if (tree->per_sample()) {
        // The spread of the light samples' trees: leaves and node words of the smallest and largest.
        const std::vector<size_t> leaves = tree->block_points(object.samples.directions.size());
        size_t fewest = 0, most = 0;
        for (size_t s = 0; s < leaves.size(); ++s) {
          if (leaves[s] < leaves[fewest]) fewest = s;
          if (leaves[s] > leaves[most]) most = s;
        }
        if (!leaves.empty()) {
          entry["sample_leaves"] = {{"fewest", leaves[fewest]}, {"most", leaves[most]}};
          entry["sample_tree_nodes"] = {{"of_fewest", tree->sample_nodes(fewest)}, {"of_most", tree->sample_nodes(most)}};
        }
      }
    }
    if (object.harmonic) entry["coefficients"] = object.values.light_samples();
    const size_t index = objects.size();
    if (index < environment_.size() && environment_[index].active) {
      const EnvironmentState& state = environment_[index];
      entry["environment"] = {{"quadrature_points", state.quadrature_points},
                              {"seconds", state.seconds},
                              {"irradiance_outside_set", luminance(Color(state.outside_set))},
                              {"clamp", state.per_sample ? "per_sample" : "combined"}};
    }
    objects.push_back(std::move(entry));
  }
  return {{"objects", objects},
          {"backend", backend_},
          {"gpu_device", gpu_context_ && vulkan_ ? gpu_context_->device_name() : ""}};
}

void LpiMethod::check_frame_dump(const ParamSet& knobs) const {
  check_vulkan_supports(volume_settings(knobs), "--dump-frame (the Vulkan kernel's inputs)");
}

void LpiMethod::dump_frame(const GBuffer& gbuffer, const ParamSet& render, const Image& output,
                           const std::string& folder) const {
  check_vulkan_supports(settings_, "--dump-frame (the Vulkan kernel's inputs)");
  for (const EnvironmentState& state : environment_)
    if (state.active)
      throw InputError("lpi --dump-frame: the scene has an environment light, whose combined volume the Vulkan "
                       "kernel does not evaluate (backend: cpu only)");
  // The CPU backend keeps no copy of the kernel's inputs: made here from the volumes.
  LpiFrameData frame;
  fill_volume_data(settings_, objects_, frame);
  fill_frame_lights(frame_, outside_mode(render), frame);
  fill_receivers(gbuffer, frame);
  // First, so that a folder that held another method's dump names lpi before lpi's files land.
  write_dump_method(folder, "lpi");
  write_lpi_frame_data(frame, folder);
  write_dump_irradiance(folder, backend_, output);
}

}  // namespace causticbench
