#include "methods/pinhole/pinhole.h"

#include <fmt/format.h>

#include "core/optics.h"
#include "core/parallel.h"
#include "gpu/cube_filter_check.h"
#include "methods/common/gpu_arrays.h"
#include "methods/pinhole/cube_filter.h"
#include "methods/pinhole/reflection_lanes.h"
#include "methods/pinhole/texel_fetch.h"
#include "methods/pinhole/throughput.h"
#include "methods/pinhole/vulkan_pinhole.h"

namespace causticbench {

PinholeMethod::PinholeMethod() = default;
PinholeMethod::~PinholeMethod() = default;

const MethodInfo& PinholeMethod::static_info() {
  static const MethodInfo info = [] {
    MethodInfo m;
    m.name = "pinhole";
    m.paper = "M. Wand, W. Strasser, \"Real-Time Caustics\", Computer Graphics Forum 22(3), 2003";
    m.summary = "Samples the reflector every frame; each sample projects the light's environment map onto the "
                "receivers like a pinhole camera, optionally with curvature-based anisotropic filtering.";
    const ParamPhase build = ParamPhase::build, frame = ParamPhase::frame, render = ParamPhase::render;
    m.params = {
        ParamSpec::integer("samples", 1000, 1, 1e7, "target number of reflector samples (pinhole cameras) per frame", frame),
        ParamSpec::choice("sampling", "neighborhood", {"random", "grid", "quantized_grid", "neighborhood"},
                          "stratification of the samples (Section 3.2)", frame),
        ParamSpec::choice("filtering", "none", {"none", "isotropic", "anisotropic"},
                          "resampling filter of the light lookups from differential point samples (Section 3.3)", build),
        ParamSpec::choice("filter_implementation", "own", {"own", "oiio", "hardware"},
                          "own: the method's footprint filter on a mip-mapped cube map, the same on both backends; "
                          "oiio: OpenImageIO's on a lat-long texture (cpu only); hardware: the device's textureGrad "
                          "(vulkan only)", build)
            .only_when("filtering", {"isotropic", "anisotropic"}),
        ParamSpec::choice("interaction", "reflect", {"reflect", "refract"},
                          "one mirror reflection, or one refraction (the variant Section 5 names)", build),
        ParamSpec::integer("environment_resolution", 256, 4, 4096, "cube map face size of the light map (paper: 256)", frame),
        ParamSpec::integer("seed", 1, 0, 4e9, "seed of the reflector sampling", frame),
        ParamSpec::choice("backend", "cpu", {"cpu", "vulkan"},
                          "cpu (multithreaded, SIMD) or vulkan (compute shader; lavapipe without a GPU)", build),
        ParamSpec::real("epsilon", -1.0, 0.0, 1e6,
                        "added to the squared distance against the singularity; -1: the squared sample spacing A/N", render)
            .or_special(-1.0),
        ParamSpec::boolean("attenuation", true, "cosines over squared distance; false reproduces Fig. 5", render),
        ParamSpec::boolean("fresnel", true, "angle-dependent reflectance (conductor or dielectric Fresnel)", render),
    };
    Capabilities& c = m.capabilities;
    c.reflection = true;
    c.refraction = true;
    c.multiple_bounces = false;
    c.directional_light = c.environment_light = true;
    // Measured in tests/test_capabilities.cpp: a point light near the reflector, taken as distant from its
    // centre, lights parts of it the light cannot reach (energy 3.4x the reference's there).
    c.point_light = false;
    c.moving_light = c.moving_objects = true;
    c.occlusion = false;
    // E_c is irradiance, which does not depend on the receiver's BRDF (measured equal on a glossy floor).
    c.non_lambertian_receivers = true;
    // A closed glass object (two interfaces) is beyond the paper's single refraction: measured on the glass
    // sphere of configs/scenes/capabilities/glass/ (README, "Refraction: one interface").
    c.notes = {{"refraction", "a single refraction (interaction: refract), e.g. a water surface over a pool floor; the "
                              "receiver is taken to lie in the glass, so a closed object's exit interface is not "
                              "modelled (a glass sphere over a floor: energy 1.31, what one interface gives)"},
               {"point_light", "approximated as distant from the reflectors' centre, as the paper does: right for a light "
                               "far from the reflector, measurably wrong for one near it (Liu 2008 Table 1 agrees)"},
               {"non_lambertian_receivers", "E_c is irradiance, independent of the receiver's BRDF; each sample's "
                                            "light direction is known, so a glossy BRDF could be shaded (Liu 2008 "
                                            "Table 1 marks pinhole so)"},
               {"occlusion", "no visibility between reflector samples and receivers beyond back-face culling"},
               {"multiple_bounces", "one specular interaction only"}};
    m.frame_dump = true;
    m.quick_knobs = {"samples=64", "environment_resolution=32"};
    m.counters = {counter_quantity("samples", "samples", "reflector samples (pinholes) per frame"),
                  counter_quantity("cube_map_texels", "texels", "texels of the light's cube map"),
                  counter_quantity("sample_evaluations", "evaluations",
                                   "receiver pixels x samples of the last frame (the pairs the kernel accounts for)")};
    return m;
  }();
  return info;
}

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
    packed_map_ = lit_everywhere && build_.text("filtering") == "none" && build_.text("interaction") == "reflect"
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

namespace {

// Direction towards the light seen through a sample (normal n) from a receiver in `direction` (unit,
// receiver to sample), and the cosine at the sample. Returns false when no light can pass (back
// face, total internal reflection).
inline bool light_direction(const Vec3& direction, const Vec3& normal_in, bool two_sided, float ior,
                            bool refraction, Vec3& to_light, float& cos_sample) {
  Vec3 normal = normal_in;
  // Reflection: the receiver faces the reflecting side. Refraction: the receiver is inside the
  // medium (behind the outward normal) and the ray leaves through the sample towards the light.
  cos_sample = refraction ? glm::dot(normal, direction) : -glm::dot(normal, direction);
  if (cos_sample <= 0.0f) {
    if (!two_sided) return false;
    normal = -normal;
    cos_sample = -cos_sample;
  }
  if (!refraction) {
    to_light = reflect(direction, normal);
    return true;
  }
  return refract(direction, -normal, 1.0f / ior, to_light);
}

}  // namespace

Image PinholeMethod::render(const GBuffer& gbuffer, const ParamSet& params) {
  Image result(gbuffer.width, gbuffer.height, 3);
  const std::vector<ReflectorSample>& samples = samples_.samples;
  if (samples.empty()) return result;
  evaluations_ = static_cast<double>(gbuffer.receiver_count()) * static_cast<double>(samples.size());
  if (vulkan_) {
    fill_receivers(gbuffer, params, frame_data_);
    return image_of_rgba(gbuffer.width, gbuffer.height, vulkan_->render(frame_data_, gpu_render_ms_));
  }
  const float epsilon = epsilon_of(params);
  const bool attenuation = params.boolean("attenuation");
  Interaction interaction{build_.text("interaction") == "refract", params.boolean("fresnel")};
  const std::string& filtering = build_.text("filtering");
  const bool filtered = filtering != "none" && (filtered_map_ || cube_filter_);
  // The skip of footprints that reach no light changes nothing (methods/pinhole/tests/test_pinhole.cpp); the variable
  // turns it off to show that.
  const bool skip = std::getenv("CAUSTICBENCH_PINHOLE_NO_SKIP") == nullptr;
  const bool anisotropic = filtering == "anisotropic";
  const float footprint_radius = this->footprint_radius();
  // Structure of arrays for the hot loop (pixels x samples): positions and normals contiguous.
  const size_t count = samples.size();
  // Padded to a multiple of 8 for the vector kernel; padding samples have a zero normal, so they never face.
  const size_t padded = (count + 7) / 8 * 8;
  std::vector<float> px(padded, 0.0f), py(padded, 0.0f), pz(padded, 1e6f), nx(padded, 0.0f), ny(padded, 0.0f),
      nz(padded, 0.0f);
  for (size_t i = 0; i < count; ++i) {
    px[i] = samples[i].position.x;
    py[i] = samples[i].position.y;
    pz[i] = samples[i].position.z;
    nx[i] = samples[i].normal.x;
    ny[i] = samples[i].normal.y;
    nz[i] = samples[i].normal.z;
  }
  std::vector<float> two_sided(padded, 0.0f);
  for (size_t i = 0; i < count; ++i) two_sided[i] = samples[i].two_sided ? 1.0f : 0.0f;
  const float sample_area = samples.front().area;
  if (!filtered && !interaction.refract) {
    // The common case (Fig. 4 to 7): geometry in vectorised blocks, then a lookup per facing sample,
    // with the throughput from a table per material (methods/pinhole/throughput.h).
    std::vector<ThroughputTable> tables;
    std::vector<uint16_t> table_of(count);
    for (size_t i = 0; i < count; ++i) {
      auto found = std::find_if(tables.begin(), tables.end(),
                                [&](const ThroughputTable& t) { return t.material() == sample_materials_[i]; });
      if (found == tables.end()) found = tables.insert(tables.end(), ThroughputTable(*sample_materials_[i], interaction.fresnel));
      table_of[i] = static_cast<uint16_t>(found - tables.begin());
    }
    table_error_ = 0.0f;
    for (const ThroughputTable& table : tables) table_error_ = std::max(table_error_, table.max_error());
    // The same for the vector fetch (texel_fetch.h): the tables' values flat, the table index as int32.
    std::vector<float> throughput_values;
    for (const ThroughputTable& table : tables)
      for (const Color& value : table.values()) throughput_values.insert(throughput_values.end(), {value.r, value.g, value.b});
    std::vector<int32_t> table_index(table_of.begin(), table_of.end());
    table_index.resize(padded, 0);  // the vector fetch reads whole groups of 8
    const bool vector_fetch = vector_fetch_enabled();
    // A block of samples is taken through every pixel of a chunk before the next block: a sample's
    // texels move by about one texel from one pixel to the next, so the block's texels stay cached. Each
    // pixel's sum still adds the blocks in order, so the output is the same bit for bit as pixel by
    // pixel.
    constexpr size_t kBlock = 256, kPixels = 64;
    parallel_blocks(gbuffer.pixel_count(), kPixels, [&](size_t begin, size_t end, size_t) {
      alignas(32) float texel_s[kBlock], texel_t[kBlock], weight[kBlock], cos_sample[kBlock];
      alignas(32) int face[kBlock], block[kBlock];
      const std::vector<uint8_t>& occupied = cube_map_.occupancy();
      uint16_t indices[kBlock];
      const float resolution = static_cast<float>(cube_map_.resolution());
      const uint32_t* packed = packed_map_.texels().empty() ? nullptr : packed_map_.texels().data();
      size_t pixels[kPixels];
      Color sums[kPixels];
      size_t receivers = 0;
      for (size_t pixel = begin; pixel < end; ++pixel) {
        if (gbuffer.receiver[pixel]) pixels[receivers++] = pixel;
      }
      std::fill(sums, sums + receivers, Color(0.0f));
      for (size_t first = 0; first < count; first += kBlock) {
        size_t n = std::min(kBlock, count - first);
        for (size_t r = 0; r < receivers; ++r) {
          const size_t pixel = pixels[r];
          Color& sum = sums[r];
          reflection_block(ReflectionBlock{(n + 7) / 8 * 8, &px[first], &py[first], &pz[first], &nx[first], &ny[first],
                                           &nz[first], &two_sided[first], gbuffer.position[pixel], gbuffer.normal[pixel],
                                           epsilon, sample_area, resolution,
                                           static_cast<float>(cube_map_.occupancy_blocks()), attenuation, face, block,
                                           texel_s, texel_t, weight, cos_sample});
          // Under an environment map (packed) every block is lit: the vector fetch compacts the facing
          // samples itself, by a permutation eight at a time.
          if (packed && vector_fetch) {
            fetch_sum_avx2(FetchBlock{face, texel_s, texel_t, weight, cos_sample, nullptr, (n + 7) / 8 * 8,
                                      cube_map_.texels().data(), packed, packed_map_.unit_bits(), cube_map_.resolution(),
                                      throughput_values.data(), table_index.data() + first, tables.size() == 1},
                           sum);
            continue;
          }
          // Compact the facing samples that look into a lit part of the map without a branch (about
          // half face away, at random, which a branch would mispredict), then look them up.
          size_t facing = 0;
          for (size_t j = 0; j < n; ++j) {
            indices[facing] = static_cast<uint16_t>(j);
            facing += (weight[j] > 0.0f) & (occupied[block[j]] != 0);
          }
          size_t k = 0;
          if (vector_fetch)
            k = fetch_sum_avx2(FetchBlock{face, texel_s, texel_t, weight, cos_sample, indices, facing,
                                          cube_map_.texels().data(), nullptr, 0, cube_map_.resolution(),
                                          throughput_values.data(), table_index.data() + first, false},
                               sum);
          for (; k < facing; ++k) {
            size_t j = indices[k];
            Color radiance = cube_map_.lookup_texel(face[j], texel_s[j], texel_t[j]);
            if (radiance.r + radiance.g + radiance.b <= 0.0f) continue;
            sum += radiance * tables[table_of[first + j]](cos_sample[j]) * weight[j];
          }
        }
      }
      for (size_t r = 0; r < receivers; ++r) result.set_rgb(pixels[r], sums[r]);
    });
    return result;
  }
  // Differential point samples: the points p + r u, p + r v and their normals n + r dn/du, n + r dn/dv
  // (normalised) depend on the sample only; made once here rather than for every pixel.
  std::vector<Vec3> moved_positions, moved_normals;
  if (filtered) {
    for (const ReflectorSample& sample : samples) {
      moved_positions.insert(moved_positions.end(), {sample.position + footprint_radius * sample.direction_u,
                                                     sample.position + footprint_radius * sample.direction_v});
      moved_normals.insert(moved_normals.end(), {glm::normalize(sample.normal + footprint_radius * sample.normal_derivative_u),
                                                 glm::normalize(sample.normal + footprint_radius * sample.normal_derivative_v)});
    }
  }
  // The vector pre-skip (filtered_skip_lanes) where the own filter looks up a compact light.
  const bool prefilter = cube_filter_ && skip && !interaction.refract && !cube_filter_->lit_everywhere();
  std::vector<std::vector<float>> moved_arrays(12, std::vector<float>(padded, 0.0f));
  if (prefilter) {
    for (int k = 0; k < 2; ++k) std::fill(moved_arrays[3 * k + 2].begin(), moved_arrays[3 * k + 2].end(), 1e6f);
    for (size_t i = 0; i < count; ++i) {
      for (int k = 0; k < 2; ++k) {
        for (int c = 0; c < 3; ++c) {
          moved_arrays[3 * k + c][i] = moved_positions[2 * i + k][c];
          moved_arrays[6 + 3 * k + c][i] = moved_normals[2 * i + k][c];
        }
      }
    }
  }
  const std::vector<float> cone_data = prefilter ? cube_filter_->lit_cone_data() : std::vector<float>();
  parallel_blocks(gbuffer.pixel_count(), 64, [&](size_t begin, size_t end, size_t) {
    constexpr size_t kBlock = 256;
    alignas(32) float keep[kBlock];
    for (size_t pixel = begin; pixel < end; ++pixel) {
      if (!gbuffer.receiver[pixel]) continue;
      const Vec3 x = gbuffer.position[pixel], receiver_normal = gbuffer.normal[pixel];
      Color sum(0.0f);
      auto evaluate = [&](size_t i) {
        Vec3 offset(px[i] - x.x, py[i] - x.y, pz[i] - x.z);
        float distance2 = glm::dot(offset, offset);
        float cos_receiver_scaled = glm::dot(receiver_normal, offset);
        if (cos_receiver_scaled <= 0.0f) return;  // back-face culling at the receiver, before any root
        const ReflectorSample& sample = samples[i];
        Vec3 direction = offset * (1.0f / std::sqrt(distance2));
        float cos_receiver = glm::dot(receiver_normal, direction);
        const Material& material = *sample_materials_[i];
        Vec3 to_light;
        float cos_sample;
        if (!light_direction(direction, Vec3(nx[i], ny[i], nz[i]), sample.two_sided, material.ior, interaction.refract,
                             to_light, cos_sample)) {
          return;
        }
        Color radiance;
        if (filtered) {
          // Differential point sample: reflection (or refraction) directions at p + r u and p + r v
          // with the normals n + r dn/du and n + r dn/dv give the footprint's two gradients.
          Vec3 gradients[2];
          for (int k = 0; k < 2; ++k) {
            Vec3 moved = moved_positions[2 * i + k] - x;
            const Vec3& moved_normal = moved_normals[2 * i + k];
            Vec3 moved_light;
            float unused_cos;
            gradients[k] = light_direction(glm::normalize(moved), moved_normal, sample.two_sided, material.ior,
                                           interaction.refract, moved_light, unused_cos)
                               ? moved_light - to_light
                               : Vec3(0.0f);
          }
          radiance = cube_filter_ ? cube_filter_->lookup(to_light, gradients[0], gradients[1], anisotropic, skip)
                                  : filtered_map_->lookup(to_light, gradients[0], gradients[1], anisotropic);
        } else {
          radiance = cube_map_.lookup(to_light);
        }
        if (radiance.r + radiance.g + radiance.b <= 0.0f) return;
        float geometry = attenuation ? cos_sample * cos_receiver / (distance2 + epsilon) : 1.0f;
        sum += radiance * light_throughput(material, interaction, cos_sample) * (geometry * sample.area);
      };
      if (!prefilter) {
        for (size_t i = 0; i < count; ++i) evaluate(i);
      } else {
        for (size_t first = 0; first < count; first += kBlock) {
          size_t n = std::min(kBlock, count - first);
          FilteredSkipBlock block{(n + 7) / 8 * 8, &px[first], &py[first], &pz[first], &nx[first], &ny[first], &nz[first],
                                  {}, x, cone_data.data(), cone_data.size() / 4, cube_filter_->support_per_texel(),
                                  0.5f * static_cast<float>(cube_filter_->level_size(0)), anisotropic, keep};
          for (int k = 0; k < 12; ++k) block.moved[k] = &moved_arrays[k][first];
          filtered_skip(block);
          for (size_t j = 0; j < n; ++j) {
            if (keep[j] != 0.0f) evaluate(first + j);
          }
        }
      }
      result.set_rgb(pixel, sum);
    }
  });
  return result;
}

float PinholeMethod::epsilon_of(const ParamSet& params) const {
  // Negative: the paper's default, the squared sample spacing.
  const double knob = params.real("epsilon");
  return static_cast<float>(knob >= 0.0 ? knob : samples_.spacing * samples_.spacing);
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

void PinholeMethod::fill_receivers(const GBuffer& gbuffer, const ParamSet& params, PinholeFrameData& frame) const {
  frame.width = static_cast<uint32_t>(gbuffer.width);
  frame.height = static_cast<uint32_t>(gbuffer.height);
  fill_receiver_arrays(gbuffer, frame.receiver_positions, frame.receiver_normals);
  frame.epsilon = epsilon_of(params);
  frame.area = samples_.samples.empty() ? 0.0f : samples_.samples.front().area;
  frame.attenuation = params.boolean("attenuation") ? 1 : 0;
  frame.fresnel = params.boolean("fresnel") ? 1 : 0;
  frame.refraction = build_.text("interaction") == "refract" ? 1 : 0;
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

nlohmann::json PinholeMethod::record() const {
  return {{"backend", build_.text("backend")},
          {"gpu_device", gpu_context_ ? gpu_context_->device_name() : ""},
          {"gpu_sampler_warning", sampler_note_},
          {"filter_implementation", filter_implementation_},
          {"samples", samples_.samples.size()},
          {"reflector_area", samples_.total_area},
          {"sample_spacing", samples_.spacing},
          {"cell_or_diameter", samples_.cell_or_diameter},
          {"throughput_table_max_error", table_error_},
          {"packed_texels_max_error", packed_map_.max_relative_error()}};
}

}  // namespace causticbench
