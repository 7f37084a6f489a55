// csl's Vulkan backend on the method's side: the frame's spot lights and their images as the kernel
// reads them (methods/csl/frame_data.h), the render that dispatches it (methods/csl/vulkan_csl.h) and
// `--dump-frame`. The spot lights are the CPU's: the static set, or what update() interpolated for a
// dynamic light; only their evaluation moves to the device.
#include <cmath>
#include <cstring>

#include "core/errors.h"
#include "methods/common/gpu_arrays.h"
#include "methods/csl/csl.h"
#include "methods/csl/vulkan_csl.h"

namespace causticbench {

using namespace csl;

struct CslMethod::GpuState {
  std::unique_ptr<gpu::Context> context;
  std::unique_ptr<VulkanCsl> vulkan;
  CslFrameData frame;
  GpuImageIndex images;
  bool images_uploaded = false;  // every image of this build is on the device
  bool lights_uploaded = false;  // this frame's spot lights are
  bool last_render = false;      // the last render ran on the device
  double kernel_ms = 0.0;
};

CslMethod::CslMethod() = default;
CslMethod::~CslMethod() = default;

namespace {

uint32_t bits(float value) {
  uint32_t word;
  std::memcpy(&word, &value, sizeof word);
  return word;
}

// The index of `image` in frame's image arrays, appending its texels and on-axis tables on first sight.
uint32_t image_index(const IntensityImage& image, std::unordered_map<const IntensityImage*, uint32_t>& index,
                     CslFrameData& frame) {
  auto found = index.find(&image);
  if (found != index.end()) return found->second;
  const uint32_t at = frame.image_count();
  index.emplace(&image, at);
  const bool quantised = image.precision() == IntensityImage::Precision::uint16;
  frame.images.insert(frame.images.end(), {static_cast<uint32_t>(frame.texels.size()), static_cast<uint32_t>(image.size()),
                                           static_cast<uint32_t>(image.channels()), quantised ? 1u : 0u,
                                           static_cast<uint32_t>(frame.radial.size()),
                                           static_cast<uint32_t>(image.radial_bins())});
  frame.image_scalars.push_back(image.half_size());
  for (int c = 0; c < 3; ++c) frame.image_scalars.push_back(quantised && c < image.channels() ? image.scales()[c] : 1.0f);
  if (quantised) {
    // Two texels a word, the first in the low half.
    const std::vector<uint16_t>& q = image.quantised();
    for (size_t k = 0; k < q.size(); k += 2) frame.texels.push_back(q[k] | (k + 1 < q.size() ? uint32_t(q[k + 1]) << 16 : 0u));
  } else {
    for (float value : image.floats()) frame.texels.push_back(bits(value));
  }
  for (double value : image.radial_flux()) frame.radial.push_back(static_cast<float>(value));
  for (double value : image.ring_integral()) frame.radial.push_back(static_cast<float>(value));
  return at;
}

struct Source {
  const IntensityImage* image;
  float weight;
  double map[4];
};

void append_light(const SpotGeometry& geometry, int channels, double max_radius, const std::vector<Source>& sources,
                  const Color& irradiance, std::unordered_map<const IntensityImage*, uint32_t>& index, CslFrameData& frame) {
  auto push = [&](const Vec3& v, double w) {
    frame.lights.insert(frame.lights.end(), {v.x, v.y, v.z, static_cast<float>(w)});
  };
  push(geometry.origin, geometry.profile.kappa);
  push(geometry.axis, geometry.profile.beta);
  push(geometry.u, max_radius);
  push(geometry.v, channels);
  push(Vec3(irradiance.r, irradiance.g, irradiance.b), 0.0);
  float weights[4] = {0.0f, 0.0f, 0.0f, 0.0f};
  for (size_t s = 0; s < sources.size(); ++s) weights[s] = sources[s].weight;
  frame.lights.insert(frame.lights.end(), weights, weights + 4);
  uint32_t words[4] = {static_cast<uint32_t>(sources.size()), 0, 0, 0};
  for (size_t s = 0; s < CslFrameData::kMaxSources; ++s) {
    const double* map = s < sources.size() ? sources[s].map : nullptr;
    for (int k = 0; k < 4; ++k) frame.lights.push_back(map ? static_cast<float>(map[k]) : 0.0f);
    if (s < sources.size()) words[1 + s] = image_index(*sources[s].image, index, frame);
  }
  frame.light_images.insert(frame.light_images.end(), words, words + 4);
}

}  // namespace

void CslMethod::gpu_all_images(GpuImageIndex& index, CslFrameData& frame) const {
  auto add = [&](const SpotLightSet& set) {
    for (const SpotLight& light : set.lights) {
      if (light.image.size() > 0) image_index(light.image, index, frame);
    }
  };
  for (const ObjectSets& sets : objects_) {
    for (const SpotLightSet& set : sets.sets) add(set);
    if (sets.dynamic) {
      for (const SpotLightSet& set : sets.dynamic->sets) add(set);
    }
  }
}

void CslMethod::gpu_lights(GpuImageIndex& index, CslFrameData& frame) const {
  frame.lights.clear();
  frame.light_images.clear();
  frame.object_lights.clear();
  for (const ObjectFrame& view : frame_) {
    frame.object_lights.push_back(frame.light_count());
    // The CPU's order: per light, its set's spot lights, then the interpolated ones.
    for (const LightView& light : view.lights) {
      if (light.set != nullptr) {
        for (const SpotLight& spot : light.set->lights) {
          std::vector<Source> sources;
          // A stored image is a blend of one, weight 1, identity map: the same arithmetic.
          if (spot.image.size() > 0) sources.push_back(Source{&spot.image, 1.0f, {1.0, 0.0, 0.0, 1.0}});
          append_light(spot, spot.image.channels(), spot.image.max_radius(), sources, light.irradiance, index, frame);
        }
      }
      for (const InterpolatedSpotLight& spot : light.interpolated) {
        std::vector<Source> sources;
        for (int s = 0; s < spot.image.count(); ++s) {
          const BlendedImage::Source& source = spot.image.source(s);
          sources.push_back(Source{source.image, source.weight, {source.map[0], source.map[1], source.map[2], source.map[3]}});
        }
        append_light(spot.geometry, spot.image.channels(), spot.image.max_radius(), sources, light.irradiance, index, frame);
      }
    }
    frame.object_lights.push_back(frame.light_count() - frame.object_lights.back());
  }
}

void CslMethod::gpu_receivers(const GBuffer& gbuffer, const ParamSet& render, CslFrameData& frame) const {
  frame.width = static_cast<uint32_t>(gbuffer.width);
  frame.height = static_cast<uint32_t>(gbuffer.height);
  fill_receiver_arrays(gbuffer, frame.receiver_positions, frame.receiver_normals);
  // The normal's w: the pixel footprint's side, for the on-axis epsilon.
  for (size_t pixel = 0; pixel < gbuffer.pixel_count(); ++pixel) frame.receiver_normals[4 * pixel + 3] = gbuffer.footprint[pixel];
  frame.objects.clear();
  for (size_t i = 0; i < objects_.size(); ++i) {
    const ObjectFrame& view = frame_[i];
    const EvaluationSettings settings = evaluation_settings(render, objects_[i].bounds);
    auto column = [&](const glm::mat3& m, int c, float w) {
      frame.objects.insert(frame.objects.end(), {m[c].x, m[c].y, m[c].z, w});
    };
    for (int c = 0; c < 3; ++c) column(view.map.linear, c, 0.0f);
    frame.objects.insert(frame.objects.end(), {view.map.offset.x, view.map.offset.y, view.map.offset.z, view.length_scale});
    column(view.map.normals, 0, static_cast<float>(settings.axis_epsilon));
    column(view.map.normals, 1, 0.0f);
    column(view.map.normals, 2, 0.0f);
  }
  frame.intensity_correction = render.text("intensity_correction") == "on" ? 1 : 0;
  frame.on_axis = render.text("on_axis") == "epsilon" ? 1 : 0;
}

void CslMethod::forget_gpu_images() {
  if (!gpu_) return;
  gpu_->images.clear();
  gpu_->images_uploaded = false;
  gpu_->lights_uploaded = false;
}

void CslMethod::forget_gpu_lights() {
  if (gpu_) gpu_->lights_uploaded = false;
}

void CslMethod::note_cpu_render() {
  if (gpu_) gpu_->last_render = false;
}

Image CslMethod::render_vulkan(const GBuffer& gbuffer, const ParamSet& render) {
  if (!gpu_) gpu_ = std::make_unique<GpuState>();
  GpuState& gpu = *gpu_;
  if (!gpu.vulkan) {
    gpu.context = std::make_unique<gpu::Context>();
    gpu.vulkan = std::make_unique<VulkanCsl>(*gpu.context);
  }
  CslFrameData& frame = gpu.frame;
  if (!gpu.images_uploaded) {
    // Every image of the build, once: a dynamic light's frames read the images of any built facet.
    frame.images.clear(), frame.image_scalars.clear(), frame.texels.clear(), frame.radial.clear();
    gpu.images.clear();
    gpu_all_images(gpu.images, frame);
    gpu.vulkan->upload_images(frame);
    gpu.images_uploaded = true;
  }
  if (!gpu.lights_uploaded) {
    const uint32_t images = frame.image_count();
    gpu_lights(gpu.images, frame);
    if (frame.image_count() != images) gpu.vulkan->upload_images(frame);  // none expected: all are there
    gpu.vulkan->upload_lights(frame);
    gpu.lights_uploaded = true;
  }
  gpu_receivers(gbuffer, render, frame);
  Image result = image_of_rgba(gbuffer.width, gbuffer.height, gpu.vulkan->render(frame, gpu.kernel_ms));
  gpu.last_render = true;
  // As the CPU counts them: every spot light at every receiver.
  evaluations_ = static_cast<double>(gbuffer.receiver_count()) * frame.light_count();
  return result;
}

std::string CslMethod::gpu_device() const {
  return gpu_ && gpu_->last_render ? gpu_->context->device_name() : "";
}

std::optional<double> CslMethod::gpu_render_milliseconds() const {
  return gpu_ && gpu_->last_render ? std::optional<double>(gpu_->kernel_ms) : std::nullopt;
}

void CslMethod::dump_frame(const GBuffer& gbuffer, const ParamSet& render, const Image& output,
                           const std::string& folder) const {
  // Only the images this frame's spot lights read: a dynamic build's other facets stay out of the dump.
  CslFrameData frame;
  GpuImageIndex index;
  gpu_lights(index, frame);
  gpu_receivers(gbuffer, render, frame);
  check_frame_data(frame, folder);
  // First, so that a folder that held another method's dump names csl before csl's files land.
  write_dump_method(folder, "csl");
  write_csl_frame_data(frame, folder);
  write_dump_irradiance(folder, render.text("backend"), output);
}

}  // namespace causticbench
