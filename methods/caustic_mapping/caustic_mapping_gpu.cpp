// caustic_mapping's Vulkan backend on the method's side: the scene and the passes' plans as the device
// takes them (frame_data.h), the device's frame in update() with its statistics counted as the CPU counts
// its own (count_leaving, count_landing), the lookup in render(), and `--dump-frame`.
#include <algorithm>
#include <cmath>
#include <limits>

#include "core/errors.h"
#include "core/parallel.h"
#include "methods/caustic_mapping/caustic_mapping.h"
#include "methods/caustic_mapping/frame_data.h"
#include "methods/caustic_mapping/vulkan_caustic_mapping.h"
#include "methods/common/analytic_mesh.h"
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

namespace {

// Segments around an analytic shape's axis when the light views rasterise it (analytic_mesh.h): half the
// photon buffer's resolution, at least 64 and at most 512, so that a tessellated silhouette or normal
// strays from the exact surface by well under a photon-buffer texel (a sphere at 256 segments: its
// chords sag 7.5e-5 of its radius, its interpolated normals turn by under 1e-4 rad).
int raster_segments(const caustic_mapping::Settings& settings) {
  return std::clamp(2 * settings.photon_resolution, 64, 512);
}

float material_code(MaterialKind kind) {
  switch (kind) {
    case MaterialKind::mirror: return 1.0f;
    case MaterialKind::glass: return 2.0f;
    case MaterialKind::diffuse_mirror: return 3.0f;
    default: return 0.0f;
  }
}

// The depth range of `view` that holds the whole scene (its bounding sphere, with a margin).
std::pair<float, float> depth_range(const LightView& view, const BoundingSphere& scene) {
  const double centre = glm::dot(glm::dvec3(scene.center) - glm::dvec3(view.eye()), glm::dvec3(view.axis()));
  const double radius = 1.01 * scene.radius + 1e-6;
  if (view.is_orthographic()) return {static_cast<float>(centre - radius), static_cast<float>(centre + radius)};
  const double distance = glm::length(glm::dvec3(scene.center) - glm::dvec3(view.eye()));
  const double far = distance + radius;
  const double near = std::max(1e-5 * far, distance > radius ? 0.5 * (distance - radius) : 0.0);
  return {static_cast<float>(near), static_cast<float>(far)};
}

}  // namespace

void CausticMappingMethod::fill_frame_data(CausticMappingFrameData& frame) const {
  frame.search_iterations = static_cast<uint32_t>(settings_.search_iterations);
  frame.plane_hit = settings_.refine ? 1u : 0u;
  frame.splat = settings_.splat == caustic_mapping::SplatKind::point      ? 0u
                : settings_.splat == caustic_mapping::SplatKind::gaussian ? 1u
                                                                          : 2u;
  frame.refraction = settings_.refraction == caustic_mapping::Settings::Refraction::two_interface   ? 1u
                     : settings_.refraction == caustic_mapping::Settings::Refraction::one_interface ? 2u
                                                                                                    : 0u;
  frame.splat_radius = static_cast<float>(settings_.splat_radius);
  frame.splat_photons = static_cast<float>(settings_.splat_photons);
  frame.max_splat_radius = static_cast<float>(settings_.max_splat_radius);
  frame.views.clear(), frame.passes.clear();
  frame.strengths.clear(), frame.measures.clear(), frame.photon_measures.clear();
  const Tracer& tracer = *tracer_;
  const SceneFrame& scene = tracer.frame();

  // The scene's triangles, and d_N at the vertices of glass that may take two interfaces: a ray from the
  // vertex along its inward normal to the object's far side (Wyman's per-vertex precomputation). Kept
  // while no object moves or changes shape (the key: the tessellation, the refraction mode, every
  // object's transform, and the frame where a shape changes with it), so a static scene builds them once.
  const bool two = settings_.refraction != caustic_mapping::Settings::Refraction::one_interface;
  std::vector<double> key = {static_cast<double>(raster_segments(settings_)), two ? 1.0 : 0.0};
  for (size_t object = 0; object < scene.scene->objects.size(); ++object) {
    const glm::dmat4& matrix = scene.transforms[object].matrix;
    for (int column = 0; column < 4; ++column)
      for (int row = 0; row < 4; ++row) key.push_back(matrix[column][row]);
    if (scene.scene->objects[object].shape.changes_with_frame()) key.push_back(scene.frame);
  }
  if (key != geometry_.key || geometry_.scene != scene.scene) {
    geometry_.key = std::move(key);
    geometry_.scene = scene.scene;
    geometry_.vertices.clear();
    geometry_.objects.clear();
    for (size_t object = 0; object < scene.scene->objects.size(); ++object) {
      const Material& material = scene.scene->objects[object].material;
      const SurfaceMesh mesh = surface_mesh(scene, static_cast<int>(object), raster_segments(settings_));
      std::vector<float> normal_depth(mesh.positions.size(), 0.0f);
      if (material.kind == MaterialKind::glass && two)
        parallel_blocks(mesh.positions.size(), 1024, [&](size_t begin, size_t end, size_t) {
          for (size_t i = begin; i < end; ++i) {
            const Vec3 inward = -Vec3(mesh.normals[i]);
            SurfaceHit hit;
            if (tracer.intersect(Ray{Vec3(mesh.positions[i]) + inward * tracer.epsilon(), inward}, hit) &&
                hit.object == static_cast<int>(object))
              normal_depth[i] = hit.t + tracer.epsilon();
          }
        });
      for (const glm::uvec3& triangle : mesh.triangles)
        for (int corner = 0; corner < 3; ++corner) {
          const uint32_t i = triangle[corner];
          const glm::dvec3 &p = mesh.positions[i], &n = mesh.normals[i];
          geometry_.vertices.insert(geometry_.vertices.end(), {float(p.x), float(p.y), float(p.z), float(object),
                                                               float(n.x), float(n.y), float(n.z), normal_depth[i]});
        }
      auto push = [&](const Color& c, float w) {
        geometry_.objects.insert(geometry_.objects.end(), {c.r, c.g, c.b, w});
      };
      geometry_.objects.insert(geometry_.objects.end(),
                               {material_code(material.kind), material.receives_caustics() ? 1.0f : 0.0f, material.ior,
                                material.conductor ? 1.0f : 0.0f});
      push(material.reflectance, 0.0f);
      push(material.eta, 0.0f);
      push(material.k, 0.0f);
      push(material.absorption, 0.0f);
    }
  }
  frame.vertices = geometry_.vertices;
  frame.objects = geometry_.objects;

  for (const LightPass& pass : passes_) {
    if (!pass.plan.valid) continue;  // no light view: nothing to render or look up
    for (const LightView* view : {&pass.plan.receiver_view, &pass.plan.photon_view}) {
      auto push = [&](const Vec3& v, double w) { frame.views.insert(frame.views.end(), {v.x, v.y, v.z, static_cast<float>(w)}); };
      push(view->eye(), view->is_orthographic() ? 1.0 : 0.0);
      push(view->axis(), view->half_extent());
      push(view->right(), view->offset_s());
      push(view->up(), view->offset_t());
      const auto [near, far] = depth_range(*view, scene.scene_bounds);
      frame.views.insert(frame.views.end(), {near, far, 0.0f, 0.0f});
    }
    const int n = settings_.map_resolution, p = settings_.photon_resolution;
    frame.passes.insert(frame.passes.end(), {static_cast<uint32_t>(n), frame.texel_count(), frame.photon_count(),
                                             static_cast<uint32_t>(p), static_cast<uint32_t>(pass.object), 0u, 0u, 0u});
    const Color& strength = pass.plan.strength;
    frame.strengths.insert(frame.strengths.end(), {strength.r, strength.g, strength.b, 0.0f});
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) frame.measures.push_back(static_cast<float>(pass.plan.receiver_view.texel_measure(x, y, n)));
    for (int y = 0; y < p; ++y)
      for (int x = 0; x < p; ++x) frame.photon_measures.push_back(static_cast<float>(pass.plan.photon_view.texel_measure(x, y, p)));
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
  VulkanCausticMapping::Readback readback;
  gpu_->splat_ms = gpu_->vulkan->splat(frame, &readback);
  // Counted as the CPU backend counts (count_leaving, count_landing), in photon-buffer texel order.
  size_t slot = 0;
  for (LightPass& pass : passes_) {
    if (!pass.plan.valid) continue;
    const size_t texels = static_cast<size_t>(settings_.photon_resolution) * settings_.photon_resolution;
    for (size_t texel = 0; texel < texels; ++texel, ++slot) {
      const float* record = &readback.photons[16 * slot];
      caustic_mapping::Outgoing photon;
      photon.covered = record[3] != 1.0f;
      photon.second_failed = record[3] == 2.0f;
      photon.one_interface = record[7] != 0.0f;
      photon.origin = Vec3(record[0], record[1], record[2]);
      photon.direction = Vec3(record[4], record[5], record[6]);
      photon.flux = Color(record[8], record[9], record[10]);
      photon.not_modelled = record[11];
      photon.absorption = Color(record[12], record[13], record[14]);
      caustic_mapping::count_leaving(pass, photon);
      if (!photon.covered || photon.second_failed) continue;
      const float* landing = &readback.landings[4 * slot];
      const auto what = static_cast<caustic_mapping::Landing>(static_cast<uint32_t>(landing[2]));
      const Color arriving(readback.arriving[4 * slot], readback.arriving[4 * slot + 1], readback.arriving[4 * slot + 2]);
      // The photon stage counts the start's read as a step: with iterations to take, a search that read only
      // once failed at its start (with none, a start that did not converge reads once too: not counted).
      const bool at_start = what == caustic_mapping::Landing::search_failed && settings_.search_iterations > 0 &&
                            static_cast<int>(landing[3]) <= 1;
      caustic_mapping::count_landing(pass.statistics, pass.leaving.back(), what, arriving, static_cast<int>(landing[3]),
                                     at_start);
      if (what == caustic_mapping::Landing::search_failed) {
        pass.dropped.push_back(static_cast<uint32_t>(pass.leaving.size() - 1));
        pass.dropped_at_start.push_back(at_start ? 1 : 0);
      }
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
  // What the device takes, from the frame update() saw (its tracer lives until the run's frame ends) and
  // the passes' plans, which both backends keep.
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
