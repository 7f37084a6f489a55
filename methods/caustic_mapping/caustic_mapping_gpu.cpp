// caustic_mapping's Vulkan backend on the method's side: the passes' light views, receiver maps and
// leaving photons as the device takes them (frame_data.h), the device's photon stage and splats in
// update() with their statistics counted as the CPU counts its own (count_landing), the lookup in
// render(), and `--dump-frame`. The light-view passes are the CPU's (light_pass.cpp) for both backends.
#include <cmath>
#include <limits>

#include "core/errors.h"
#include "methods/caustic_mapping/caustic_mapping.h"
#include "methods/caustic_mapping/frame_data.h"
#include "methods/caustic_mapping/vulkan_caustic_mapping.h"
#include "methods/common/gpu_arrays.h"

namespace causticbench {

using caustic_mapping::LightPass;

struct CausticMappingMethod::GpuState {
  std::unique_ptr<gpu::Context> context;
  std::unique_ptr<VulkanCausticMapping> vulkan;
  CausticMappingFrameData frame;
  double splat_ms = 0.0, lookup_ms = 0.0;
  bool last_render = false;  // the last render ran on the device
};

CausticMappingMethod::CausticMappingMethod() = default;
CausticMappingMethod::~CausticMappingMethod() = default;

void CausticMappingMethod::fill_frame_data(CausticMappingFrameData& frame) const {
  frame.search_iterations = static_cast<uint32_t>(settings_.search_iterations);
  frame.plane_hit = settings_.refine ? 1u : 0u;
  frame.splat = settings_.splat == caustic_mapping::SplatKind::point      ? 0u
                : settings_.splat == caustic_mapping::SplatKind::gaussian ? 1u
                                                                          : 2u;
  frame.splat_radius = static_cast<float>(settings_.splat_radius);
  frame.splat_photons = static_cast<float>(settings_.splat_photons);
  frame.max_splat_radius = static_cast<float>(settings_.max_splat_radius);
  frame.views.clear(), frame.passes.clear(), frame.receivers.clear(), frame.measures.clear(), frame.photons.clear();
  for (const LightPass& pass : passes_) {
    const caustic_mapping::ReceiverMap& map = pass.receivers;
    if (map.resolution == 0) continue;  // no light view: nothing to splat or look up
    const LightView& view = map.view;
    auto push = [&](const Vec3& v, double w) { frame.views.insert(frame.views.end(), {v.x, v.y, v.z, static_cast<float>(w)}); };
    push(view.eye(), view.is_orthographic() ? 1.0 : 0.0);
    push(view.axis(), view.half_extent());
    push(view.right(), view.offset_s());
    push(view.up(), view.offset_t());
    const int n = map.resolution;
    frame.passes.insert(frame.passes.end(), {static_cast<uint32_t>(n), frame.texel_count(), frame.photon_count(),
                                             static_cast<uint32_t>(pass.leaving.size())});
    for (size_t texel = 0; texel < map.depth.size(); ++texel) {
      const Vec3& p = map.position[texel];
      const Vec3& normal = map.normal[texel];
      frame.receivers.insert(frame.receivers.end(), {p.x, p.y, p.z, map.depth[texel], normal.x, normal.y, normal.z, 0.0f});
    }
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) frame.measures.push_back(static_cast<float>(view.texel_measure(x, y, n)));
    for (const caustic_mapping::PhotonRay& photon : pass.leaving) {
      const Vec3 &o = photon.origin, &d = photon.direction;
      const Color &f = photon.flux, &a = photon.absorption;
      frame.photons.insert(frame.photons.end(),
                           {o.x, o.y, o.z, 0.0f, d.x, d.y, d.z, 0.0f, f.r, f.g, f.b, 0.0f, a.r, a.g, a.b, 0.0f});
    }
  }
}

void CausticMappingMethod::update_on_device() {
  if (!gpu_) {
    gpu_ = std::make_unique<GpuState>();
    gpu_->context = std::make_unique<gpu::Context>();
    gpu_->vulkan = std::make_unique<VulkanCausticMapping>(*gpu_->context);
  }
  CausticMappingFrameData& frame = gpu_->frame;
  fill_frame_data(frame);
  std::vector<float> landings, arriving;
  gpu_->splat_ms = gpu_->vulkan->splat(frame, &landings, &arriving);
  // Counted as the CPU backend counts (count_landing), in photon order.
  size_t photon = 0;
  for (LightPass& pass : passes_) {
    if (pass.receivers.resolution == 0) continue;
    for (size_t i = 0; i < pass.leaving.size(); ++i, ++photon) {
      const float* landing = &landings[4 * photon];
      const auto what = static_cast<caustic_mapping::Landing>(static_cast<uint32_t>(landing[2]));
      const Color flux(arriving[4 * photon], arriving[4 * photon + 1], arriving[4 * photon + 2]);
      caustic_mapping::count_landing(pass.statistics, pass.leaving[i], what, flux, static_cast<int>(landing[3]));
      if (what == caustic_mapping::Landing::search_failed) pass.dropped.push_back(static_cast<uint32_t>(i));
    }
  }
  gpu_->last_render = false;
}

Image CausticMappingMethod::render_on_device(const GBuffer& gbuffer) {
  CausticMappingFrameData& frame = gpu_->frame;
  frame.width = static_cast<uint32_t>(gbuffer.width);
  frame.height = static_cast<uint32_t>(gbuffer.height);
  fill_receiver_arrays(gbuffer, frame.receiver_positions, frame.receiver_normals);
  const std::vector<float> rgba = gpu_->vulkan->look_up(frame, gpu_->lookup_ms);
  gpu_->last_render = true;
  return image_of_rgba(gbuffer.width, gbuffer.height, rgba);
}

std::optional<double> CausticMappingMethod::gpu_render_milliseconds() const {
  if (!vulkan_ || !gpu_ || !gpu_->last_render) return std::nullopt;
  return gpu_->splat_ms + gpu_->lookup_ms;
}

void CausticMappingMethod::check_frame_dump(const ParamSet& knobs) const {
  if (knobs.has("intersection") && knobs.text("intersection") == "exact")
    throw InputError("caustic_mapping --dump-frame: intersection: exact traces rays through the scene's Embree tracer, "
                     "which the Vulkan backend does not have; dump an image_space run");
}

void CausticMappingMethod::dump_frame(const GBuffer& gbuffer, const ParamSet&, const Image& output,
                                      const std::string& folder) const {
  if (settings_.exact) throw InputError("caustic_mapping --dump-frame: intersection: exact has no Vulkan replay");
  // Both backends keep what the device takes (the passes' maps and leaving photons): made here from them.
  CausticMappingFrameData frame;
  fill_frame_data(frame);
  frame.width = static_cast<uint32_t>(gbuffer.width);
  frame.height = static_cast<uint32_t>(gbuffer.height);
  fill_receiver_arrays(gbuffer, frame.receiver_positions, frame.receiver_normals);
  check_frame_data(frame, folder);
  // First, so that a folder that held another method's dump names caustic_mapping before its files land.
  write_dump_method(folder, "caustic_mapping");
  write_caustic_mapping_frame_data(frame, folder);
  write_dump_irradiance(folder, vulkan_ ? "vulkan" : "cpu", output);
}

}  // namespace causticbench
