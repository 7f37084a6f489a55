// rt_photons' frame: emission maps, photons traced with their differentials (update), splats (render), and
// what a run records. The knobs are in rt_photons_info.cpp.
#include "methods/rt_photons/rt_photons.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <fmt/format.h>

#include "core/low_discrepancy.h"
#include "core/parallel.h"
#include "core/photon_tracer.h"
#include "methods/common/photon_memory.h"

namespace causticbench {

// A frame's peak holds every landed photon twice, in update's per-block vectors (kept from frame to frame
// so that later frames allocate nothing; grown by doubling, they hold up to twice their landings) and in
// the merged list render splats, and render's footprint per photon: 3 x sizeof(LandedPhoton) + 4 bytes.
constexpr double kBytesPerLanding = 3.0 * sizeof(rt_photons::LandedPhoton) + sizeof(float);

std::vector<MemoryTerm> RtPhotonsMethod::knob_memory(const PrepareContext& context, const ParamSet& knobs) const {
  const double photons = static_cast<double>(knobs.integer("photons_per_frame"));
  const double landings = deposits_per_photon_bound(context, static_cast<uint64_t>(knobs.integer("seed")),
                                                    static_cast<int>(knobs.integer("max_bounces")));
  return {MemoryTerm{{"photons_per_frame"}, photons * landings * kBytesPerLanding,
                     fmt::format("{:.3g} photons x {:.2f} landings each at most x {:.0f} bytes", photons, landings,
                                 kBytesPerLanding)}};
}

void RtPhotonsMethod::check_scene(const Scene& scene) const {
  require_specular_object(scene, "rt_photons traces photons through specular objects");
}

void RtPhotonsMethod::update(const FrameContext& frame, const ParamSet& knobs) {
  const uint64_t budget = static_cast<uint64_t>(knobs.integer("photons_per_frame"));
  const uint64_t seed = static_cast<uint64_t>(knobs.integer("seed"));
  const int resolution = static_cast<int>(knobs.integer("emission_resolution"));
  max_bounces_ = static_cast<int>(knobs.integer("max_bounces"));
  adaptive_ = knobs.text("adaptive") == "on";
  if (knobs.has("target_footprint")) target_footprint_ = knobs.real("target_footprint");
  ++updates_;
  const SceneFrame& scene = frame.frame;
  camera_ = &scene.camera;
  std::vector<BoundingSphere> targets;
  for (int object : scene.specular_objects()) targets.push_back(scene.bounds[object]);
  lights_ = scene.lights;
  grids_.clear();
  // An extended light's samples are redrawn every frame of a pass (the same in every pass).
  const int light_samples = static_cast<int>(knobs.integer("light_samples"));
  for (size_t l = 0; l < lights_.size(); ++l)
    for (rt_photons::EmissionGrid& grid :
         rt_photons::emission_grids(lights_[l], l, targets, scene.scene_bounds, resolution, light_samples, seed ^ 0x11647ull ^ (updates_ << 32)))
      grids_.push_back(std::move(grid));
  // The densities carried from the last frame, where the grids still have their shapes (else uniform).
  bool same_shape = density_.size() == grids_.size();
  for (size_t g = 0; same_shape && g < grids_.size(); ++g) same_shape = density_[g].size() == grids_[g].texel_count();
  if (!adaptive_ || !same_shape) {
    density_.assign(grids_.size(), {});
    for (size_t g = 0; g < grids_.size(); ++g) density_[g].assign(grids_[g].texel_count(), 1.0f);
  }
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
        const double flux = rt_photons::texel_flux(grids_[g], t) * density_[g][t];
        if (flux > 0.0) texels.push_back(Texel{g, t, flux, 0, 0}), total_flux += flux;
      }
  active_texels_ = texels.size();
  // Uniform: the budget spread in proportion to flux. Adapted: each texel's share scaled by its density,
  // the budget a cap (a frame whose footprints all reach the target spends less).
  double scale = static_cast<double>(budget) / total_flux;
  if (adaptive_) {
    double uniform_total = 0.0;
    for (const Texel& texel : texels) uniform_total += texel.expected / density_[texel.grid][texel.texel];
    scale = std::min(static_cast<double>(budget) / uniform_total, static_cast<double>(budget) / total_flux);
  }
  texel_refs_.clear();
  uint64_t next = 0;
  for (size_t i = 0; i < texels.size(); ++i) {
    Texel& texel = texels[i];
    texel_refs_.push_back(TexelRef{static_cast<uint32_t>(texel.grid), static_cast<uint32_t>(texel.texel),
                                   texel.expected / density_[texel.grid][texel.texel]});
    texel.expected *= scale;
    if (!(texel.expected > 0.0)) continue;
    Random draw(seed ^ 0x5eedull ^ (updates_ << 20), i);
    texel.photons = static_cast<uint64_t>(std::floor(texel.expected)) +
                    (draw.uniform_double() < texel.expected - std::floor(texel.expected) ? 1 : 0);
    texel.first = next;
    next += texel.photons;
  }
  photons_budgeted_ = next;
  PhotonTracerSettings settings;
  settings.seed = seed;
  settings.max_bounces = max_bounces_;
  const CausticPhotonTracer tracer(frame.tracer, settings);
  const auto trace_start = std::chrono::steady_clock::now();
  const size_t block = 64;
  const size_t blocks = (texels.size() + block - 1) / block;
  // Each block's landings; the vectors (and landed_) keep their capacity from frame to frame, so that a
  // frame after the first allocates nothing (first touching fresh pages cost a fifth of the update).
  std::vector<std::vector<rt_photons::LandedPhoton>>& landed = landed_blocks_;
  landed.resize(blocks);
  for (auto& block_photons : landed) block_photons.clear();
  std::vector<PhotonStats> block_stats(blocks);
  parallel_blocks(texels.size(), block, [&](size_t begin, size_t end, size_t b) {
    for (size_t i = begin; i < end; ++i) {
      const Texel& texel = texels[i];
      if (texel.photons == 0) continue;
      const rt_photons::EmissionGrid& grid = grids_[texel.grid];
      // Each frame of a pass its own photons (their points and paths), so that frames are independent
      // estimates and temporal accumulation averages their noise away; the same in every pass.
      const ShiftedSobol points(seed ^ (updates_ << 24), grid.texel_count() * texel.grid + texel.texel);
      const double share = 1.0 / texel.expected;
      // Its patch of the beam: its texel's share of the photons of every map overlapping its own.
      const float spacing = grid.texel * static_cast<float>(std::sqrt(share / grid.overlapping));
      for (uint64_t j = 0; j < texel.photons; ++j) {
        Ray ray;
        Color power;
        RayDifferential differential;
        rt_photons::emit_photon(grid, texel.texel, points.uniform(static_cast<uint32_t>(j), 0),
                                points.uniform(static_cast<uint32_t>(j), 1), points.uniform(static_cast<uint32_t>(j), 2), share,
                                ray, power, differential);
        tracer.trace_emitted((updates_ << 40) + texel.first + j, ray, power, differential, block_stats[b],
                             [&](const SurfaceHit& hit, const Vec3& arrival_normal, const Vec3&, const Color& carried,
                                 const RayDifferential& at) {
                               rt_photons::LandedPhoton photon;
                               photon.position = hit.position;
                               photon.normal = arrival_normal;
                               photon.power = carried;
                               photon.axis_u = at.dp_du * spacing;
                               photon.axis_v = at.dp_dv * spacing;
                               photon.cone_width = std::sqrt(glm::length(glm::cross(photon.axis_u, photon.axis_v)));
                               photon.texel = static_cast<uint32_t>(i);
                               landed[b].push_back(photon);
                             });
      }
    }
  });
  trace_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - trace_start).count();
  landed_.clear();
  stats_ = PhotonStats{};
  landed_flux_ = 0.0;
  size_t total = 0;
  for (size_t b = 0; b < blocks; ++b) total += landed[b].size();
  landed_.reserve(total);
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
  std::vector<float> footprint_pixels;
  const auto splat_start = std::chrono::steady_clock::now();
  Image image = rt_photons::splat_photons(landed_, *camera_, gbuffer, settings, splat_counts_, &footprint_pixels);
  splat_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - splat_start).count();
  // The first render after an update steers the next frame's emission (the others, with other render knobs
  // or pixel samples, leave it).
  if (adaptive_ && adapted_update_ != updates_) {
    adapt(footprint_pixels);
    adapted_update_ = updates_;
  }
  const double alpha = knobs.real("temporal_alpha");
  if (alpha <= 0.0) return image;
  const std::string key = fmt::format("{}|{}|{}|{}|{}", knobs.text("footprint"), settings.min_pixels, settings.max_pixels,
                                      settings.fixed_pixels, alpha);
  return accumulate(key, alpha, gbuffer, std::move(image));
}

void RtPhotonsMethod::begin_sequence() {
  updates_ = 0;
  density_.clear();
  history_.clear();
  adapted_update_ = 0;
  adaptations_ = 0;
  last_density_change_ = 0.0;
  reprojected_ = rejected_ = 0;
}

// A texel's density stays within [1/4, 16] of uniform. A focus's footprints shrink to nothing whatever the
// density (the differentials' parallelogram collapses), so a texel there would give up its photons
// without end, and the few left would carry its whole flux: spikes (relMSE 4.7 against uniform's 0.11 on the
// turning bunny with no floor on the density).
constexpr double kLeastDensity = 0.25, kMostDensity = 16.0;

// Per texel, the geometric mean of its photons' unclamped footprints (pixels) over those some pixel sees;
// the footprint's radius goes as one over the square root of the photon density, so density x (footprint /
// target)^2 would bring it to the target. Damped (the geometric mean of the old and that, each step within
// 2x), a texel none of whose photons is seen keeping its own. Where the densities then ask for more than
// the budget (a flux-weighted mean above 1) they are scaled down to it, so that they say what is emitted:
// the map then converges to equal footprints over the texels, above the target.
void RtPhotonsMethod::adapt(const std::vector<float>& footprint_pixels) {
  std::vector<double> log_sum(texel_refs_.size(), 0.0);
  std::vector<uint32_t> count(texel_refs_.size(), 0);
  for (size_t p = 0; p < landed_.size(); ++p) {
    if (!(footprint_pixels[p] > 0.0f)) continue;
    log_sum[landed_[p].texel] += std::log(static_cast<double>(footprint_pixels[p]));
    ++count[landed_[p].texel];
  }
  std::vector<double> before(texel_refs_.size()), after(texel_refs_.size());
  double flux = 0.0, weighted = 0.0;
  for (size_t i = 0; i < texel_refs_.size(); ++i) {
    before[i] = density_[texel_refs_[i].grid][texel_refs_[i].texel];
    after[i] = before[i];
    if (count[i] > 0) {
      const double footprint = std::exp(log_sum[i] / count[i]);
      const double wanted = std::clamp((footprint / target_footprint_) * (footprint / target_footprint_), 0.25, 4.0);
      after[i] = std::clamp(before[i] * std::sqrt(wanted), kLeastDensity, kMostDensity);
    }
    flux += texel_refs_[i].flux;
    weighted += texel_refs_[i].flux * after[i];
  }
  const double scale = weighted > flux && weighted > 0.0 ? flux / weighted : 1.0;
  double change = 0.0;
  for (size_t i = 0; i < texel_refs_.size(); ++i) {
    after[i] *= scale;
    change += texel_refs_[i].flux * std::abs(after[i] / before[i] - 1.0);
    density_[texel_refs_[i].grid][texel_refs_[i].texel] = static_cast<float>(after[i]);
  }
  last_density_change_ = flux > 0.0 ? change / flux : 0.0;
  ++adaptations_;
}

// out = alpha x the previous frame's output where this pixel's point was + (1 - alpha) x this frame's, where
// the previous frame saw the same point there (within two pixel footprints); this frame's alone elsewhere.
Image RtPhotonsMethod::accumulate(const std::string& key, double alpha, const GBuffer& gbuffer, Image current) {
  History& history = history_[key];
  if (history.update != updates_) {
    history.previous = std::move(history.image);
    history.previous_positions = std::move(history.positions);
    history.previous_camera = std::move(history.camera);
    history.update = updates_;
  }
  Image result = current;
  if (history.previous_camera && history.previous.pixel_count() > 0) {
    const int width = history.previous.width(), height = history.previous.height();
    for (size_t pixel = 0; pixel < gbuffer.pixel_count(); ++pixel) {
      if (!gbuffer.receiver[pixel]) continue;
      const Vec3& point = gbuffer.position[pixel];
      const std::optional<glm::dvec2> at = history.previous_camera->image_position(point);
      bool found = false;
      if (at && at->x >= 0.0 && at->y >= 0.0 && at->x < width && at->y < height) {
        const size_t before = static_cast<size_t>(at->y) * width + static_cast<size_t>(at->x);
        if (glm::length(history.previous_positions[before] - point) <= 2.0f * gbuffer.footprint[pixel]) {
          result.set_rgb(pixel, history.previous.rgb(before) * static_cast<float>(alpha) +
                                    current.rgb(pixel) * static_cast<float>(1.0 - alpha));
          found = true;
        }
      }
      found ? ++reprojected_ : ++rejected_;
    }
  }
  history.image = result;
  history.positions = gbuffer.position;
  history.camera = *camera_;
  return result;
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
  // Per light: its samples (one for a delta light) and its maps' active texels in all.
  nlohmann::json lights = nlohmann::json::array();
  for (size_t l = 0; l < lights_.size(); ++l) {
    size_t active = 0, samples = 0;
    nlohmann::json shape = nlohmann::json::object();
    for (const rt_photons::EmissionGrid& grid : grids_) {
      if (grid.light != l) continue;
      for (uint8_t a : grid.active) active += a;
      samples = static_cast<size_t>(grid.samples);
      shape = {{"faces", grid.faces}, {"resolution", grid.resolution}, {"texel", grid.texel}};
    }
    shape["light"] = lights_[l].light ? lights_[l].light->name : "";
    shape["samples"] = samples;
    shape["active_texels"] = active;
    lights.push_back(shape);
  }
  return {{"emission", lights},
          {"rays", stats_.rays},
          {"paths_cut_at_max_bounces", stats_.cut},
          {"landed_flux", landed_flux_},
          {"hidden_flux", splat_counts_.hidden_flux},
          {"splatted_flux", splat_counts_.splatted_flux},
          {"photons_budgeted", photons_budgeted_},
          // Rates of the last frame's two passes (wall clock, all threads): the target is photons
          // traced and splatted per second; a splat's cost goes with its pixels.
          {"trace_seconds", trace_seconds_},
          {"splat_seconds", splat_seconds_},
          {"photons_traced_per_second", trace_seconds_ > 0.0 ? stats_.emitted / trace_seconds_ : 0.0},
          {"photons_splatted_per_second", splat_seconds_ > 0.0 ? landed_.size() / splat_seconds_ : 0.0},
          {"pixels_splatted_per_second", splat_seconds_ > 0.0 ? splat_counts_.pixels / splat_seconds_ : 0.0},
          {"adaptive", adaptive_},
          {"adaptations", adaptations_},
          {"last_density_change", last_density_change_},
          {"reprojected_pixels", reprojected_},
          {"rejected_pixels", rejected_},
          {"carried_between_frames",
           "reset at every pass: the emission densities (adaptive: on) and, per render knob set, the last frame's "
           "output with its positions and camera (temporal_alpha > 0); nothing else"}};
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
