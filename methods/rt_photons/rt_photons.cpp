// rt_photons' frame: emission maps, photons traced with their differentials (update), splats (render), and
// what a run records. The knobs are in rt_photons_info.cpp.
#include "methods/rt_photons/rt_photons.h"

#include <cmath>

#include <fmt/format.h>

#include "core/low_discrepancy.h"
#include "core/parallel.h"
#include "core/photon_tracer.h"

namespace causticbench {

void RtPhotonsMethod::check_scene(const Scene& scene) const {
  require_specular_object(scene, "rt_photons traces photons through specular objects");
}

void RtPhotonsMethod::update(const FrameContext& frame, const ParamSet& knobs) {
  const uint64_t budget = static_cast<uint64_t>(knobs.integer("photons_per_frame"));
  const uint64_t seed = static_cast<uint64_t>(knobs.integer("seed"));
  const int resolution = static_cast<int>(knobs.integer("emission_resolution"));
  max_bounces_ = static_cast<int>(knobs.integer("max_bounces"));
  const SceneFrame& scene = frame.frame;
  camera_ = &scene.camera;
  std::vector<BoundingSphere> targets;
  for (int object : scene.specular_objects()) targets.push_back(scene.bounds[object]);
  lights_ = scene.lights;
  grids_.clear();
  for (const LightFrame& light : lights_) grids_.push_back(rt_photons::emission_grid(light, targets, scene.scene_bounds, resolution));
  // Expected photons per texel in proportion to its flux, the budget in all; each texel then emits the
  // floor of its share or one more (a draw per texel), each photon carrying flux / expected: unbiased, and
  // within a few photons of the budget.
  struct Texel {
    size_t grid, texel;
    double expected;
    uint64_t photons, first;
  };
  std::vector<Texel> texels;
  double total_flux = 0.0;
  for (size_t g = 0; g < grids_.size(); ++g)
    for (size_t t = 0; t < grids_[g].texel_count(); ++t)
      if (grids_[g].active[t]) {
        const double flux = rt_photons::texel_flux(grids_[g], t);
        if (flux > 0.0) texels.push_back(Texel{g, t, flux, 0, 0}), total_flux += flux;
      }
  active_texels_ = texels.size();
  uint64_t next = 0;
  for (size_t i = 0; i < texels.size(); ++i) {
    Texel& texel = texels[i];
    texel.expected *= static_cast<double>(budget) / total_flux;
    Random draw(seed ^ 0x5eedull, i);
    texel.photons = static_cast<uint64_t>(std::floor(texel.expected)) +
                    (draw.uniform_double() < texel.expected - std::floor(texel.expected) ? 1 : 0);
    texel.first = next;
    next += texel.photons;
  }
  PhotonTracerSettings settings;
  settings.seed = seed;
  settings.max_bounces = max_bounces_;
  const CausticPhotonTracer tracer(frame.tracer, settings);
  const size_t block = 64;
  const size_t blocks = (texels.size() + block - 1) / block;
  std::vector<std::vector<rt_photons::LandedPhoton>> landed(blocks);
  std::vector<PhotonStats> block_stats(blocks);
  parallel_blocks(texels.size(), block, [&](size_t begin, size_t end, size_t b) {
    for (size_t i = begin; i < end; ++i) {
      const Texel& texel = texels[i];
      const rt_photons::EmissionGrid& grid = grids_[texel.grid];
      const ShiftedSobol points(seed, grid.texel_count() * texel.grid + texel.texel);
      const double share = 1.0 / texel.expected;
      const float spacing = grid.texel * static_cast<float>(std::sqrt(share));
      for (uint64_t j = 0; j < texel.photons; ++j) {
        Ray ray;
        Color power;
        RayDifferential differential;
        rt_photons::emit_photon(grid, texel.texel, points.uniform(static_cast<uint32_t>(j), 0),
                                points.uniform(static_cast<uint32_t>(j), 1), share, ray, power, differential);
        tracer.trace_emitted(texel.first + j, ray, power, differential, block_stats[b],
                             [&](const SurfaceHit& hit, const Vec3& arrival_normal, const Vec3&, const Color& carried,
                                 const RayDifferential& at) {
                               rt_photons::LandedPhoton photon;
                               photon.position = hit.position;
                               photon.normal = arrival_normal;
                               photon.power = carried;
                               photon.axis_u = at.dp_du * spacing;
                               photon.axis_v = at.dp_dv * spacing;
                               photon.cone_width = std::sqrt(glm::length(glm::cross(photon.axis_u, photon.axis_v)));
                               landed[b].push_back(photon);
                             });
      }
    }
  });
  landed_.clear();
  stats_ = PhotonStats{};
  landed_flux_ = 0.0;
  for (size_t b = 0; b < blocks; ++b) {
    for (const rt_photons::LandedPhoton& photon : landed[b]) landed_flux_ += luminance(photon.power);
    landed_.insert(landed_.end(), landed[b].begin(), landed[b].end());
    stats_.add(block_stats[b]);
  }
  cut_flux_ = stats_.cut_flux;
}

Image RtPhotonsMethod::render(const GBuffer& gbuffer, const ParamSet& knobs) {
  rt_photons::SplatSettings settings;
  settings.footprint = rt_photons::footprint_kind(knobs.text("footprint"));
  settings.min_pixels = static_cast<float>(knobs.real("min_footprint"));
  settings.max_pixels = static_cast<float>(knobs.real("max_footprint"));
  if (knobs.has("fixed_footprint")) settings.fixed_pixels = static_cast<float>(knobs.real("fixed_footprint"));
  splat_counts_ = rt_photons::SplatCounts{};
  return rt_photons::splat_photons(landed_, *camera_, gbuffer, settings, splat_counts_);
}

size_t RtPhotonsMethod::memory_bytes() const {
  size_t bytes = landed_.size() * sizeof(rt_photons::LandedPhoton);
  for (const rt_photons::EmissionGrid& grid : grids_) bytes += grid.active.size();
  return bytes;
}

Counters RtPhotonsMethod::counters() const {
  return {{"photons_emitted", static_cast<double>(stats_.emitted)},
          {"photons_landed", static_cast<double>(landed_.size())},
          {"photons_splatted", static_cast<double>(splat_counts_.splatted)},
          {"splatted_pixels", static_cast<double>(splat_counts_.pixels)},
          {"footprints_widened", static_cast<double>(splat_counts_.clamped_small)},
          {"footprints_narrowed", static_cast<double>(splat_counts_.clamped_large)},
          {"active_texels", static_cast<double>(active_texels_)}};
}

nlohmann::json RtPhotonsMethod::record() const {
  nlohmann::json lights = nlohmann::json::array();
  for (const rt_photons::EmissionGrid& grid : grids_) {
    size_t active = 0;
    for (uint8_t a : grid.active) active += a;
    lights.push_back({{"faces", grid.faces}, {"resolution", grid.resolution}, {"active_texels", active}, {"texel", grid.texel}});
  }
  return {{"emission", lights},
          {"rays", stats_.rays},
          {"paths_cut_at_max_bounces", stats_.cut},
          {"landed_flux", landed_flux_},
          {"hidden_flux", splat_counts_.hidden_flux},
          {"splatted_flux", splat_counts_.splatted_flux},
          {"carried_between_frames", "nothing: every frame's emission map and photons are its own"}};
}

std::optional<LostFlux> RtPhotonsMethod::lost_flux(const FrameContext&, const GBuffer&, const ParamSet&) {
  LostFlux lost;
  const double total = landed_flux_ + cut_flux_;
  lost.fraction = total > 0.0 ? cut_flux_ / total : 0.0;
  lost.what = "caustic flux of photons still bouncing after max_bounces";
  lost.knob = "max_bounces";
  lost.advice = fmt::format("raise max_bounces (now {}): {} paths were cut", max_bounces_, stats_.cut);
  return lost;
}

}  // namespace causticbench
