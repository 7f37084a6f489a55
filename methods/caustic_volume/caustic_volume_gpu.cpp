// caustic_volume's Vulkan backend on the method's side: the volumes and their footprints as the device
// takes them (frame_data.h), the render that draws them (vulkan_caustic_volume.h) with its counters, and
// `--dump-frame`. The volumes are the CPU's (update()); only the tests of the receiver points move.
#include <algorithm>
#include <cmath>

#include "core/errors.h"
#include "methods/caustic_volume/caustic_volume.h"
#include "methods/caustic_volume/frame_data.h"
#include "methods/caustic_volume/vulkan_caustic_volume.h"
#include "methods/common/gpu_arrays.h"

namespace causticbench {

struct CausticVolumeMethod::GpuState {
  std::unique_ptr<gpu::Context> context;
  std::unique_ptr<VulkanCausticVolume> vulkan;
  CausticVolumeFrameData frame;
  uint64_t volumes_of_update = 0;  // the update whose volumes `frame` holds (0: none)
  double kernel_ms = 0.0;
  bool last_render = false;  // the last render ran on the device
};

CausticVolumeMethod::CausticVolumeMethod() = default;
CausticVolumeMethod::~CausticVolumeMethod() = default;

namespace {

// A footprint as triangles covering it once (a fan over its convex hull), each corner pushed a pixel
// outwards from the hull's centre so that rounding keeps no point of the volume out; the whole image
// where a corner lies behind the camera; a hull of no area (a volume seen edge on) as its bounding box
// widened by a pixel.
void add_footprint(const CausticVolumeMethod::Footprint& footprint, int width, int height, float volume,
                   std::vector<float>& triangles) {
  auto corner = [&](double x, double y) { triangles.insert(triangles.end(), {float(x), float(y), volume, 0.0f}); };
  auto rectangle = [&](double x0, double y0, double x1, double y1) {
    corner(x0, y0), corner(x1, y0), corner(x0, y1);
    corner(x0, y1), corner(x1, y0), corner(x1, y1);
  };
  if (footprint.whole_image) return rectangle(0.0, 0.0, width, height);
  const std::vector<glm::dvec2>& hull = footprint.hull;
  double area = 0.0;
  glm::dvec2 lower(1e300), upper(-1e300), centre(0.0);
  for (size_t i = 0; i < hull.size(); ++i) {
    const glm::dvec2 &a = hull[i], &b = hull[(i + 1) % hull.size()];
    area += a.x * b.y - a.y * b.x;
    lower = glm::min(lower, a), upper = glm::max(upper, a);
    centre += a / double(hull.size());
  }
  if (hull.size() < 3 || std::abs(area) < 1e-6) return rectangle(lower.x - 1.0, lower.y - 1.0, upper.x + 1.0, upper.y + 1.0);
  std::vector<glm::dvec2> pushed(hull.size());
  for (size_t i = 0; i < hull.size(); ++i) {
    const glm::dvec2 away = hull[i] - centre;
    const double length = glm::length(away);
    pushed[i] = length > 0.0 ? hull[i] + away / length : hull[i];
  }
  for (size_t i = 1; i + 1 < pushed.size(); ++i) {
    corner(pushed[0].x, pushed[0].y);
    corner(pushed[i].x, pushed[i].y);
    corner(pushed[i + 1].x, pushed[i + 1].y);
  }
}

}  // namespace

void CausticVolumeMethod::fill_frame_data(const GBuffer& gbuffer, caustic_volume::Intensity intensity,
                                          CausticVolumeFrameData& frame) const {
  frame.width = static_cast<uint32_t>(gbuffer.width);
  frame.height = static_cast<uint32_t>(gbuffer.height);
  fill_receiver_arrays(gbuffer, frame.receiver_positions, frame.receiver_normals);
  frame.receiver_objects.assign(gbuffer.object.begin(), gbuffer.object.end());
  frame.intensity = intensity == caustic_volume::Intensity::constant ? 1u : 0u;
  fill_volume_data(gbuffer.width, gbuffer.height, frame);
}

void CausticVolumeMethod::fill_volume_data(int width, int height, CausticVolumeFrameData& frame) const {
  frame.volumes.clear();
  frame.footprints.clear();
  for (size_t v = 0; v < volumes_.size(); ++v) {
    const caustic_volume::Volume& volume = volumes_[v];
    auto push = [&](const glm::dvec3& a, double w) {
      frame.volumes.insert(frame.volumes.end(), {float(a.x), float(a.y), float(a.z), float(w)});
    };
    auto colour = [](const Color& c) { return glm::dvec3(c.r, c.g, c.b); };
    push(volume.origin[0], volume.t_max);
    push(volume.origin[1], volume.area_in);
    push(volume.origin[2], volume.self_gap);
    push(volume.direction[0], volume.object);
    push(volume.direction[1], 0.0);
    push(volume.direction[2], 0.0);
    for (int i = 0; i < 3; ++i) push(colour(volume.arriving[i]), volume.ring_area_in[i]);
    for (int i = 0; i < 3; ++i)
      push(glm::dvec3(volume.ring_area_out[i][0], volume.ring_area_out[i][1], volume.ring_area_out[i][2]), 0.0);
    push(volume.mean_direction, 0.0);
    push(colour(volume.absorption), 0.0);
    push(volume.lower, 0.0);
    push(volume.upper, 0.0);
    for (int j = 0; j < 3; ++j) push(volume.k[j], volume.k_dot_d0[j]);
    add_footprint(footprints_[v], width, height, static_cast<float>(v), frame.footprints);
  }
}

Image CausticVolumeMethod::render_on_device(const GBuffer& gbuffer, caustic_volume::Intensity intensity) {
  if (!gpu_) {
    gpu_ = std::make_unique<GpuState>();
    gpu_->context = std::make_unique<gpu::Context>();
    gpu_->vulkan = std::make_unique<VulkanCausticVolume>(*gpu_->context);
  }
  // The volumes and footprints are the update's: built once for the renders that follow it (pixel samples,
  // repetitions), the receivers every render.
  CausticVolumeFrameData& frame = gpu_->frame;
  const bool same_image =
      frame.width == static_cast<uint32_t>(gbuffer.width) && frame.height == static_cast<uint32_t>(gbuffer.height);
  if (gpu_->volumes_of_update != update_count_ || !same_image) {
    fill_volume_data(gbuffer.width, gbuffer.height, frame);
    gpu_->volumes_of_update = update_count_;
  }
  frame.width = static_cast<uint32_t>(gbuffer.width);
  frame.height = static_cast<uint32_t>(gbuffer.height);
  fill_receiver_arrays(gbuffer, frame.receiver_positions, frame.receiver_normals);
  frame.receiver_objects.assign(gbuffer.object.begin(), gbuffer.object.end());
  frame.intensity = intensity == caustic_volume::Intensity::constant ? 1u : 0u;
  std::vector<float> counts;
  const std::vector<float> rgba = gpu_->vulkan->render(gpu_->frame, gpu_->kernel_ms, &counts);
  // The same counters as the CPU's, summed per pixel by the blending (exact in float to 2^24 a pixel).
  double tests = 0.0, hits = 0.0;
  for (size_t pixel = 0; pixel < gbuffer.pixel_count(); ++pixel) tests += counts[2 * pixel], hits += counts[2 * pixel + 1];
  point_tests_ = static_cast<uint64_t>(tests);
  sheets_ = static_cast<uint64_t>(hits);
  shadow_rays_ = 0;
  gpu_->last_render = true;
  return image_of_rgba(gbuffer.width, gbuffer.height, rgba);
}

std::optional<double> CausticVolumeMethod::gpu_render_milliseconds() const {
  if (!gpu_ || !gpu_->last_render) return std::nullopt;
  return gpu_->kernel_ms;
}

void CausticVolumeMethod::check_frame_dump(const ParamSet& knobs) const {
  if (knobs.has("occlusion") && knobs.text("occlusion") == "shadow_rays")
    throw InputError("caustic_volume --dump-frame: occlusion: shadow_rays traces rays through the scene's Embree "
                     "tracer, which the Vulkan backend does not have; dump a run with occlusion: none");
}

void CausticVolumeMethod::dump_frame(const GBuffer& gbuffer, const ParamSet& render, const Image& output,
                                     const std::string& folder) const {
  const caustic_volume::Intensity intensity = render.text("intensity") == "constant"
                                                  ? caustic_volume::Intensity::constant
                                                  : caustic_volume::Intensity::interpolated;
  CausticVolumeFrameData frame;
  fill_frame_data(gbuffer, intensity, frame);
  check_frame_data(frame, folder);
  // First, so that a folder that held another method's dump names caustic_volume before its files land.
  write_dump_method(folder, "caustic_volume");
  write_caustic_volume_frame_data(frame, folder);
  const bool vulkan = render.has("backend") && render.text("backend") == "vulkan";
  write_dump_irradiance(folder, vulkan ? "vulkan" : "cpu", output);
}

}  // namespace causticbench
