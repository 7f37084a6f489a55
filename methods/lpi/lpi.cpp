// lpi's lifecycle: prepare (plan, shoot or load, the backend), update (this frame's light samples and
// environment weights), and what a run records. The knobs are in lpi_info.cpp, the build in
// lpi_build.cpp and precompute.cpp, the per-pixel work in lpi_render.cpp.
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
#include "methods/lpi/orientation_choice.h"
#include "methods/lpi/volume_radius.h"
#include "methods/lpi/vulkan_lpi.h"
#include "methods/common/spherical_harmonics.h"

namespace causticbench {

using namespace lpi;

LpiMethod::LpiMethod() = default;
LpiMethod::~LpiMethod() = default;

void LpiMethod::check_scene(const Scene& scene) const {
  require_specular_object(scene, "lpi precomputes the caustics of specular objects");
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
                            {"volume_radius_bounding_radii", object.volume_radius},
                            {"volume_radius_why", object.volume_radius_reason},
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
          {"orientation", settings_.orientation == Orientation::paper ? "paper" : "vector"},
          {"orientation_why", orientation_reason_},
          {"backend", backend_},
          {"gpu_device", gpu_context_ && vulkan_ ? gpu_context_->device_name() : ""}};
}

// Probe photons from this frame's lights at each object, through the whole scene: the flux of the
// objects' caustics that first lands beyond the ball each was sampled in (under `outside: clamp` or
// `fade` it is rendered from the ball's surface value, under `zero` not at all: either way the volume
// does not hold it), and in the paper orientation the light inside the balls its cosine does not
// render (caustic_reach.h, paper_orientation_share), net of the light it renders in excess elsewhere:
// the light account compares energies, and a net excess is not lost.
std::optional<LostFlux> LpiMethod::lost_flux(const FrameContext& frame, const GBuffer&, const ParamSet&) {
  BallLoss loss;
  for (const ObjectVolumes& object : objects_)
    loss.add(frame.frame, frame.tracer, object.object, object.bounds, object.volume_radius);
  const double needed = loss.needed;
  LostFlux lost;
  lost.fraction = loss.fraction();
  const double cosine = settings_.orientation == Orientation::paper ? loss.paper_orientation_loss() : 0.0;
  if (cosine > 0.0) {
    lost.fraction = std::min(1.0, lost.fraction + cosine);
    if (cosine >= loss.fraction()) {
      lost.what = fmt::format("caustic light the paper orientation's cosine does not render on these receivers ({:.1f} "
                              "%), and light landing outside the sampled ball ({:.1f} %)",
                              100.0 * cosine, 100.0 * loss.fraction());
      lost.knob = "orientation";
      lost.advice = settings_.orientation_auto
                        ? fmt::format("set orientation: vector (auto kept the paper's: its cosine renders the probes' "
                                      "light within {:.0f} % over the rendered frames)",
                                      100.0 * kPaperOrientationTolerance)
                        : fmt::format("set orientation: vector (auto chooses it where the paper's cosine renders the "
                                      "probes' light more than {:.0f} % off)",
                                      100.0 * kPaperOrientationTolerance);
      return lost;
    }
  }
  lost.what = cosine > 0.0 ? fmt::format("caustic flux whose first receiver hit lies outside the sampled ball ({:.1f} "
                                         "%), and light the paper orientation's cosine does not render ({:.1f} %)",
                                         100.0 * loss.fraction(), 100.0 * cosine)
                           : "caustic flux whose first receiver hit lies outside the sampled ball";
  lost.knob = "volume_radius";
  const double cap = volume_radius_cap(settings_);
  if (settings_.volume_radius > 0.0) {
    lost.advice = fmt::format("set volume_radius: auto (this frame needs about {:.3g} bounding radii{})", needed,
                              needed > cap ? fmt::format(", beyond the {:.3g} this storage resolves", cap) : "");
  } else {
    lost.advice = fmt::format("the receivers lie beyond {:.3g} bounding radii, the largest ball auto chooses at this "
                              "resolution; raise the storage's resolution or set volume_radius (needs about {:.3g})",
                              cap, needed);
  }
  return lost;
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
