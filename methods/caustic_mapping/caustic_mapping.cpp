// caustic_mapping's lifecycle: every pass of the frame in update(), the lookup in render(); its knobs
// are in caustic_mapping_info.cpp, one pass (light, object) in light_pass.cpp.
#include "methods/caustic_mapping/caustic_mapping.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "core/errors.h"
#include "core/parallel.h"
#include "methods/caustic_mapping/pass_parts.h"

namespace causticbench {

using caustic_mapping::LightPass;

void CausticMappingMethod::check_scene(const Scene& scene) const {
  require_specular_object(scene, "caustic_mapping renders photon buffers of the specular objects");
}

void CausticMappingMethod::update(const FrameContext& frame, const ParamSet& frame_knobs) {
  const caustic_mapping::Settings settings = caustic_mapping::Settings::from(frame_knobs);
  settings_ = settings;
  vulkan_ = frame_knobs.has("backend") && frame_knobs.text("backend") == "vulkan";
  passes_.clear();
  statistics_ = caustic_mapping::PassStatistics{};
  skipped_lights_.clear();
  tracer_ = &frame.tracer;
  const std::vector<int> objects = frame.frame.specular_objects();
  for (const LightFrame& light : frame.frame.lights) {
    // An environment has no one light view: not modelled (Liu 2008, Table 1), and said in the record.
    if (light.kind != LightKind::directional && light.kind != LightKind::point) {
      skipped_lights_.push_back(light.light->name);
      continue;
    }
    for (int object : objects) {
      // The CPU plans every pass; the CPU backend traces the rest, the Vulkan backend rasterises it.
      if (vulkan_) {
        passes_.push_back(caustic_mapping::planned_pass(frame.tracer, light, object, settings));
        continue;
      }
      passes_.push_back(caustic_mapping::begin_pass(frame.tracer, light, object, settings));
      caustic_mapping::land_and_splat(frame.tracer, settings, passes_.back());
    }
  }
  if (vulkan_) update_on_device();
  for (const LightPass& pass : passes_) statistics_.add(pass.statistics);
}

Image CausticMappingMethod::render(const GBuffer& gbuffer, const ParamSet&) {
  if (vulkan_) return render_on_device(gbuffer);
  Image result(gbuffer.width, gbuffer.height, 3);
  parallel_blocks(gbuffer.pixel_count(), 1024, [&](size_t begin, size_t end, size_t) {
    for (size_t pixel = begin; pixel < end; ++pixel) {
      if (!gbuffer.receiver[pixel]) continue;
      Color irradiance(0.0f);
      for (const LightPass& pass : passes_)
        caustic_mapping::add_lookup(pass, gbuffer.position[pixel], gbuffer.normal[pixel], irradiance);
      result.set_rgb(pixel, irradiance);
    }
  });
  return result;
}

size_t CausticMappingMethod::memory_bytes() const {
  size_t bytes = 0;
  for (const LightPass& pass : passes_) {
    const caustic_mapping::ReceiverMap& map = pass.receivers;
    bytes += map.position.size() * sizeof(Vec3) + map.normal.size() * sizeof(Vec3) + map.depth.size() * sizeof(float) +
             pass.density.size() * sizeof(float) + pass.leaving.size() * sizeof(caustic_mapping::PhotonRay) +
             pass.dropped.size() * sizeof(uint32_t) + pass.dropped_at_start.size();
  }
  return bytes;
}

// The peak of a pass: the photon buffer (front and back surfaces, travel, flux, flags: about 80 bytes a
// texel) and the photons leaving (about 60), the receiver map (28 bytes a texel) and the caustic map
// (24 bytes of flux while splatting, 12 kept); the kept maps of every pass.
std::vector<MemoryTerm> CausticMappingMethod::knob_memory(const PrepareContext& context, const ParamSet& knobs) const {
  const double photons = std::pow(static_cast<double>(knobs.integer("photon_resolution")), 2.0);
  const double texels = std::pow(static_cast<double>(knobs.integer("caustic_map_resolution")), 2.0);
  size_t lights = 0;
  for (const LightFrame& light : context.rest.lights) lights += light.kind == LightKind::directional || light.kind == LightKind::point;
  const double passes = static_cast<double>(std::max<size_t>(1, lights * context.rest.specular_objects().size()));
  return {MemoryTerm{{"photon_resolution"}, photons * 200.0,
                     fmt::format("{:.3g} photon-buffer texels x about 200 bytes (buffer, photons leaving, landed)", photons)},
          MemoryTerm{{"caustic_map_resolution"}, texels * (28.0 + 24.0 + 12.0 * passes),
                     fmt::format("{:.3g} map texels x (28 receiver + 24 splat + 12 x {:g} passes kept) bytes", texels, passes)}};
}

Counters CausticMappingMethod::counters() const {
  return {{"photons", static_cast<double>(statistics_.photons)},
          {"photons_landed", static_cast<double>(statistics_.landed)},
          {"search_failures", static_cast<double>(statistics_.search_failed)},
          {"receiver_map_reads", static_cast<double>(statistics_.search_steps)}};
}

nlohmann::json CausticMappingMethod::record() const {
  nlohmann::json passes = nlohmann::json::array();
  for (const LightPass& pass : passes_) {
    const caustic_mapping::PassStatistics& s = pass.statistics;
    passes.push_back({{"light", pass.light_name},
                      {"object", pass.object},
                      {"light_view", pass.receivers.view.is_orthographic() ? "orthographic" : "perspective"},
                      {"caustic_map_half_extent", pass.receivers.view.half_extent()},
                      {"photon_buffer_half_extent", pass.photon_window_half_extent},
                      {"photons", s.photons},
                      {"landed", s.landed},
                      {"search_failed", s.search_failed},
                      {"search_failed_at_start", s.search_failed_at_start},
                      {"second_interface_failed", s.second_interface_failed},
                      {"outside_map", s.outside_map},
                      {"one_interface", s.one_interface},
                      {"flux_beyond_widest_window", s.flux_outside_window}});
  }
  nlohmann::json record = {{"passes", passes}};
  if (!skipped_lights_.empty()) record["lights_not_modelled"] = skipped_lights_;
  if (statistics_.flux_leaving > 0.0)
    record["fresnel_reflection_not_modelled"] = statistics_.flux_not_modelled / statistics_.flux_leaving;
  return record;
}

// The flux that leaves the objects towards a receiver and that no photon delivers. A photon the search
// dropped is followed here with an exact ray (untimed): one that meets no receiver leaves the scene (a
// mirror sphere sends most of its light to the sky), which the method loses nothing by; one that meets a
// receiver is light the image-space estimate lost. Second interfaces that found no way out and photons
// beyond the caustic map are lost as they are.
std::optional<LostFlux> CausticMappingMethod::lost_flux(const FrameContext& frame, const GBuffer&, const ParamSet&) {
  LostFlux lost;
  const caustic_mapping::PassStatistics& s = statistics_;
  double search_lost = 0.0, search_lost_at_start = 0.0, escaped = 0.0, absorbed = 0.0;
  for (const LightPass& pass : passes_) {
    std::vector<double> arriving(pass.dropped.size(), 0.0);
    parallel_blocks(pass.dropped.size(), 1024, [&](size_t begin, size_t end, size_t) {
      for (size_t i = begin; i < end; ++i) {
        SurfaceHit hit;
        const caustic_mapping::PhotonRay& photon = pass.leaving[pass.dropped[i]];
        if (first_receiver(
                frame.tracer, Ray{photon.origin + photon.direction * frame.tracer.epsilon(), photon.direction}, hit,
                pass.object))
          arriving[i] = luminance(photon.flux * glm::exp(-photon.absorption * glm::length(hit.position - photon.origin)));
        else
          arriving[i] = -1.0;
      }
    });
    // A photon that meets a receiver loses what would have arrived (the rest of its flux the medium
    // absorbs); one that meets none left the scene with all of it.
    for (size_t i = 0; i < pass.dropped.size(); ++i) {
      const double flux = luminance(pass.leaving[pass.dropped[i]].flux);
      if (arriving[i] >= 0.0) {
        search_lost += arriving[i];
        if (i < pass.dropped_at_start.size() && pass.dropped_at_start[i]) search_lost_at_start += arriving[i];
        absorbed += flux - arriving[i];
      } else {
        escaped += flux;
      }
    }
  }
  lost.what = "flux leaving the specular objects towards a receiver that no photon delivers: image-space searches "
              "that left the light view or did not converge (checked with an exact ray), second interfaces not "
              "modelled (total internal reflection, an exit off the object), receivers outside the caustic map or "
              "hidden from the light, and a near point light's light beyond the photon buffer's widest window "
              "(an upper bound)";
  // The larger share names the knob. Glass's Fresnel reflection, which the method does not follow at all,
  // is in the record (fresnel_reflection_not_modelled), not here: no knob recovers it.
  if (search_lost + s.flux_outside_map >= s.flux_second_interface && search_lost_at_start > 0.5 * search_lost) {
    // Most of the light the search loses (what exact rays find a receiver for, not what leaves the scene)
    // is from searches that never started: more iterations cannot help (issue 52: a sun 3 degrees above
    // the floor fails every search at 5 and at 20 iterations alike). The Vulkan backend has no exact rays.
    lost.knob = "intersection";
    lost.advice = fmt::format("set {}intersection: exact: {:.0f} % of the light the search loses is from searches "
                              "that could not start, the light seeing no receiver behind the photon's own texel (a "
                              "light grazing the receivers sees past them), which no search_iterations changes",
                              vulkan_ ? "backend: cpu and " : "", 100.0 * search_lost_at_start / search_lost);
  } else if (search_lost + s.flux_outside_map >= s.flux_second_interface) {
    lost.knob = "search_iterations";
    lost.advice = "raise search_iterations, or set intersection: exact to measure what the image-space search loses";
  } else {
    lost.knob = "refraction";
    lost.advice = "the two-interface approximation finds no way out for this light; set refraction: one_interface to compare";
  }
  const double reaching = s.flux_leaving - s.flux_not_modelled - escaped - absorbed;
  const double missing = search_lost + s.flux_second_interface + s.flux_outside_map + s.flux_outside_window;
  lost.fraction = reaching > 0.0 ? std::clamp(missing / reaching, 0.0, 1.0) : 0.0;
  return lost;
}

}  // namespace causticbench
