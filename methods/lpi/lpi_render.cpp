// lpi's per-pixel work (render): every receiver point reads each object's volume for this frame's
// light samples, on the CPU or through the Vulkan kernel.
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
#include "methods/common/spherical_harmonics.h"

namespace causticbench {

using namespace lpi;

Outside lpi::outside_mode(const ParamSet& render) {
  const std::string& outside = render.text("outside");
  return outside == "clamp" ? Outside::clamp : outside == "fade" ? Outside::fade : Outside::zero;
}


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


}  // namespace causticbench
