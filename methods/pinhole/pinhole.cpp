// pinhole's lifecycle: prepare (the reflectors and the backend), update (the reflector samples and
// the light map of this frame), and what a run records. The knobs are in pinhole_info.cpp, the
// per-pixel work in pinhole_render.cpp.
#include "methods/pinhole/pinhole.h"

#include <algorithm>

#include <fmt/format.h>

#include "core/optics.h"
#include "core/parallel.h"
#include "gpu/cube_filter_check.h"
#include "methods/common/caustic_reach.h"
#include "methods/common/gpu_arrays.h"
#include "methods/pinhole/cube_filter.h"
#include "methods/pinhole/reflection_lanes.h"
#include "methods/pinhole/texel_fetch.h"
#include "methods/pinhole/throughput.h"
#include "methods/pinhole/vulkan_pinhole.h"

namespace causticbench {

PinholeMethod::PinholeMethod() = default;
PinholeMethod::~PinholeMethod() = default;

std::vector<int> pinhole_reflectors(const Scene& scene, const std::string& interaction) {
  std::vector<int> objects;
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    MaterialKind kind = scene.objects[i].material.kind;
    bool reflects = kind == MaterialKind::mirror || kind == MaterialKind::diffuse_mirror || kind == MaterialKind::glass;
    if (interaction == "refract" ? kind == MaterialKind::glass : reflects) objects.push_back(static_cast<int>(i));
  }
  return objects;
}

void PinholeMethod::check_scene(const Scene& scene) const {
  for (const char* interaction : {"reflect", "refract"}) {
    std::vector<int> objects = pinhole_reflectors(scene, interaction);
    if (objects.empty()) continue;
    SceneFrame frame(scene, 0);
    for (int object : objects) {
      if (!(object_area(frame, object) > 0.0)) {
        throw InputError(fmt::format("{}: object '{}' is a reflector of zero area: pinhole cannot sample it",
                                     scene.source, scene.objects[object].name));
      }
    }
  }
}

void PinholeMethod::prepare(const PrepareContext& context, const ParamSet& build) {
  const Scene& scene = context.scene;
  reflectors_ = pinhole_reflectors(scene, build.text("interaction"));
  if (reflectors_.empty()) {
    throw InputError(fmt::format("{}: pinhole with interaction '{}' needs at least one {} object", scene.source,
                                 build.text("interaction"), build.text("interaction") == "refract" ? "glass" : "specular"));
  }
  build_ = build;
  scene_ = &scene;
  interaction_ = build.text("interaction");
  any_refracts_ = false;
  for (int object : reflectors_) any_refracts_ = any_refracts_ || pinhole_refracts(interaction_, scene.objects[object].material);
  filter_implementation_ = build.text("filtering") == "none" ? "" : build.text("filter_implementation");
  if (filter_implementation_ == (build.text("backend") == "vulkan" ? "oiio" : "hardware")) {
    throw InputError(fmt::format("pinhole: filter_implementation '{}' is not available on the {} backend (own, or {})",
                                 filter_implementation_, build.text("backend"),
                                 build.text("backend") == "vulkan" ? "hardware" : "oiio"));
  }
  // A new scene or new build knobs: nothing of the last frame's light map carries over.
  cube_map_lights_.reset();
  packed_map_ = PackedTexels();
  filtered_map_.reset();
  cube_filter_.reset();
  frame_data_ = PinholeFrameData{};
  sampler_note_.clear();
  if (build.text("backend") != "vulkan") {
    vulkan_.reset();
    return;
  }
  if (!gpu_context_) gpu_context_ = std::make_unique<gpu::Context>();
  if (!vulkan_) vulkan_ = std::make_unique<VulkanPinhole>(*gpu_context_);
  if (filter_implementation_ == "hardware") {
    // Filtered lookups are only what `filtering` says if the device's sampler follows textureGrad's
    // gradients; lavapipe's anisotropic sampler does not. The run goes on, and its record says so.
    gpu::CubeFilterCheck check = gpu::cached_cube_filter_check(*gpu_context_, build.text("filtering") == "anisotropic");
    if (!check.honours_gradients) {
      sampler_note_ = gpu_context_->device_name() + ": " + check.summary() + "; this run's filtering is the driver's, not the method's";
      fmt::print(stderr, "warning: {}\n", sampler_note_);
    }
  }
}

void PinholeMethod::update(const FrameContext& context, const ParamSet& knobs) {
  samples_ = sample_reflectors(context.frame, reflectors_, static_cast<size_t>(knobs.integer("samples")),
                               parse_sampling_strategy(knobs.text("sampling")), static_cast<uint64_t>(knobs.integer("seed")));
  const int resolution = static_cast<int>(knobs.integer("environment_resolution"));
  sample_materials_.clear();
  for (const ReflectorSample& sample : samples_.samples) sample_materials_.push_back(&scene_->objects[sample.object].material);
  // The light is distant from the reflectors' centre (the area-weighted mean of their samples).
  Vec3 center(0.0f);
  for (const ReflectorSample& sample : samples_.samples) center += sample.position;
  if (!samples_.samples.empty()) center /= static_cast<float>(samples_.samples.size());
  DistantLights lights(context.frame, center);
  // The map depends only on the lights as seen from the reflectors: rebuilt when they change (a moving
  // light or reflector), reused otherwise, as a renderer would keep a static environment map.
  // (A new map resolution, a frame knob, also rebuilds it.)
  bool lights_changed = !cube_map_lights_ || !(*cube_map_lights_ == lights) || cube_map_.resolution() != resolution;
  if (lights_changed) {
    cube_map_ = LightCubeMap(lights, resolution);
    cube_map_lights_ = std::make_unique<DistantLights>(lights);
    const std::vector<uint8_t>& occupied = cube_map_.occupancy();
    const bool lit_everywhere = std::find(occupied.begin(), occupied.end(), 0) == occupied.end();
    packed_map_ = lit_everywhere && build_.text("filtering") == "none" && !any_refracts_
                      ? PackedTexels(cube_map_.texels())
                      : PackedTexels();
  }
  // The flat arrays the Vulkan backend and --dump-frame use; the cube map is copied when it changes.
  if (lights_changed) {
    frame_data_.resolution = cube_map_.resolution();
    frame_data_.cube_map = cube_map_.texels();
  }
  frame_data_.sample_positions.clear();
  frame_data_.sample_normals.clear();
  frame_data_.materials.clear();
  frame_data_.differentials.clear();
  std::vector<const Material*> materials;
  for (size_t i = 0; i < samples_.samples.size(); ++i) {
    const ReflectorSample& sample = samples_.samples[i];
    size_t index = std::find(materials.begin(), materials.end(), sample_materials_[i]) - materials.begin();
    if (index == materials.size()) materials.push_back(sample_materials_[i]);
    frame_data_.sample_positions.insert(frame_data_.sample_positions.end(),
                                        {sample.position.x, sample.position.y, sample.position.z, sample.two_sided ? 1.0f : 0.0f});
    frame_data_.sample_normals.insert(frame_data_.sample_normals.end(),
                                      {sample.normal.x, sample.normal.y, sample.normal.z, static_cast<float>(index)});
  }
  for (const Material* material : materials) {
    float kind = material->kind == MaterialKind::glass ? 2.0f : (material->conductor ? 1.0f : 0.0f);
    frame_data_.materials.insert(frame_data_.materials.end(),
                                 {material->reflectance.r, material->reflectance.g, material->reflectance.b, kind,
                                  material->eta.r, material->eta.g, material->eta.b, material->ior,
                                  material->k.r, material->k.g, material->k.b, 0.0f});
  }
  if (build_.text("filtering") != "none") {
    // The denser neighbourhood for the regression: three sample spacings across.
    estimate_differentials(samples_, 1.5 * samples_.spacing);
    frame_data_.filtering = build_.text("filtering") == "anisotropic" ? 2 : 1;
    frame_data_.footprint_radius = footprint_radius();
    for (const ReflectorSample& sample : samples_.samples) {
      for (const Vec3& v : {sample.direction_u, sample.direction_v, sample.normal_derivative_u, sample.normal_derivative_v}) {
        frame_data_.differentials.insert(frame_data_.differentials.end(), {v.x, v.y, v.z, 0.0f});
      }
    }
    if (!vulkan_ && filter_implementation_ == "oiio" && (lights_changed || !filtered_map_)) {
      filtered_map_ = std::make_unique<FilteredLightMap>(lights, resolution * 2);
    }
    if (filter_implementation_ == "own" && (lights_changed || !cube_filter_)) {
      cube_filter_ = std::make_unique<CubeFilter>(cube_map_.texels(), cube_map_.resolution());
      lights_changed = true;  // the Vulkan backend uploads the filter's levels with the map
    }
    frame_data_.own_filter = filter_implementation_ == "own" ? 1 : 0;
    if (vulkan_ && filter_implementation_ == "own" && lights_changed) frame_data_.filter_levels = cube_filter_->texels();
  }
  if (vulkan_) {
    vulkan_->upload_samples(frame_data_);
    if (lights_changed) vulkan_->upload_light_map(frame_data_);
  }
  if (build_.text("filtering") == "none") {
    samples_.dense.clear();
    samples_.dense.shrink_to_fit();
  }
}

size_t PinholeMethod::memory_bytes() const {
  return samples_.samples.size() * (sizeof(ReflectorSample) + sizeof(const Material*)) + cube_map_.memory_bytes() +
         packed_map_.texels().size() * sizeof(uint32_t) +
         (filtered_map_ ? filtered_map_->memory_bytes() : 0) + (cube_filter_ ? cube_filter_->memory_bytes() : 0);
}

Counters PinholeMethod::counters() const {
  return {{"samples", static_cast<double>(samples_.samples.size())},
          {"cube_map_texels", static_cast<double>(cube_map_.texels().size() / 3)},
          {"sample_evaluations", evaluations_}};
}

void PinholeMethod::dump_frame(const GBuffer& gbuffer, const ParamSet& params, const Image& output,
                               const std::string& folder) const {
  PinholeFrameData frame = frame_data_;
  fill_receivers(gbuffer, params, frame);
  // The CPU backend keeps the own filter's levels in cube_filter_ only; a replay needs them.
  if (frame.own_filter && frame.filter_levels.empty() && cube_filter_) frame.filter_levels = cube_filter_->texels();
  // First, so that a folder that held another method's dump names pinhole before pinhole's files land.
  write_dump_method(folder, "pinhole");
  write_frame_data(frame, folder);
  write_dump_irradiance(folder, build_.text("backend"), output);
}

namespace {

// Whether the interaction models a specular object's material: glass by refraction, a mirror (or the
// mirror part of a diffuse+mirror surface) by reflection. Under reflect, glass is sampled but only its
// Fresnel reflection is rendered; under refract, mirrors are not sampled at all.
bool models(const std::string& interaction, const Material& material) {
  return pinhole_refracts(interaction, material) == (material.kind == MaterialKind::glass);
}

}  // namespace

// Per specular object: what the run does there and why (interaction: auto decides by material).
nlohmann::json PinholeMethod::interaction_record() const {
  nlohmann::json objects = nlohmann::json::object();
  if (!scene_) return objects;
  for (size_t i = 0; i < scene_->objects.size(); ++i) {
    const Material& material = scene_->objects[i].material;
    if (!material.is_specular()) continue;
    const bool sampled = std::find(reflectors_.begin(), reflectors_.end(), static_cast<int>(i)) != reflectors_.end();
    const std::string done = !sampled ? "not sampled" : pinhole_refracts(interaction_, material) ? "refracts" : "reflects";
    objects[scene_->objects[i].name] =
        fmt::format("{} (interaction: {}, {} material{})", done, interaction_,
                    material.kind == MaterialKind::glass ? "glass" : "mirror",
                    models(interaction_, material) ? "" : "; not what the material does: lost_flux counts it");
  }
  return objects;
}

// Probe photons from this frame's lights at each specular object, through the whole scene: the flux
// that first lands on a receiver from an object whose material the interaction does not model is what
// the run cannot represent. (Paths of more than one specular interaction, such as the two refractions
// of a closed glass object, are the method's declared limit, `multiple_bounces`, not counted here.)
std::optional<LostFlux> PinholeMethod::lost_flux(const FrameContext& frame, const GBuffer&, const ParamSet&) {
  constexpr uint64_t kProbePhotons = 20000, kProbeSeed = 0x5eedba11;
  LostFlux result;
  result.knob = "interaction";
  result.advice = "set interaction: auto (glass refracts, mirrors reflect)";
  // Every specular object's material modelled (always so under auto): nothing to count, no probes.
  const std::vector<int> specular = frame.frame.specular_objects();
  if (std::all_of(specular.begin(), specular.end(),
                  [&](int object) { return models(interaction_, scene_->objects[object].material); })) {
    result.what = "nothing: the interaction models every specular object's material";
    return result;
  }
  double total = 0.0, lost = 0.0;
  std::vector<std::string> names;
  for (int object : specular) {
    const CausticReach reach = probe_caustic_reach(frame.frame, frame.tracer, object, BuildSpaceMap{},
                                                   BoundingSphere{Vec3(0.0f), 1.0f}, kProbePhotons, kProbeSeed);
    total += reach.total_flux;
    const Material& material = scene_->objects[object].material;
    if (models(interaction_, material)) continue;
    lost += reach.total_flux;
    names.push_back("'" + scene_->objects[object].name + "'");
  }
  result.fraction = total > 0.0 ? std::min(1.0, lost / total) : 0.0;
  result.what = fmt::format("caustic flux of {}, whose material interaction: {} does not model", fmt::join(names, ", "),
                            interaction_);
  return result;
}

nlohmann::json PinholeMethod::record() const {
  return {{"backend", build_.text("backend")},
          {"gpu_device", gpu_context_ ? gpu_context_->device_name() : ""},
          {"gpu_sampler_warning", sampler_note_},
          {"filter_implementation", filter_implementation_},
          {"interaction", interaction_record()},
          {"samples", samples_.samples.size()},
          {"reflector_area", samples_.total_area},
          {"sample_spacing", samples_.spacing},
          {"cell_or_diameter", samples_.cell_or_diameter},
          {"throughput_table_max_error", table_error_},
          {"packed_texels_max_error", packed_map_.max_relative_error()}};
}

}  // namespace causticbench
