// prt's lifecycle: prepare (plan, shoot), update (the frame's lighting, l = M L per cell), render (the
// clamped-cosine sum at each receiver point), and what a run records. The knobs are in prt_info.cpp,
// the build cache's view in prt_build.cpp.
#include "methods/prt/prt.h"

#include <algorithm>
#include <chrono>

#include <fmt/format.h>

#include "core/parallel.h"
#include "core/progress.h"
#include "methods/common/ball_radius.h"

namespace causticbench {

void PrtMethod::check_scene(const Scene& scene) const {
  require_specular_object(scene, "prt precomputes the transfer of specular objects");
}

void PrtMethod::plan(const PrepareContext& context, const ParamSet& build) {
  settings_ = prt::transfer_settings(build);
  scene_ = &context.scene;
  objects_.clear();
  projector_ = std::make_unique<prt::LightingProjector>(settings_.bands);
  full_projector_ = std::make_unique<prt::LightingProjector>(prt::response_bands(settings_.source_directions));
  for (int object : context.rest.specular_objects()) {
    ObjectTransfer transfer;
    transfer.object = object;
    transfer.name = context.scene.objects[object].name;
    const Scene alone = build_space_scene(context.scene, object);
    const SceneFrame frame(alone, 0.0);
    transfer.bounds = frame.bounds[0];
    const BallRadius radius =
        choose_ball_radius(context, object, transfer.bounds, settings_.volume_radius, settings_.grid_resolution);
    transfer.volume_radius = radius.radii;
    transfer.volume_radius_reason = radius.reason;
    if (radius.capped && radius.lost_at_cap > kLostFluxWarning)
      fmt::print(stderr, "warning: prt: object '{}': {}; raise grid_resolution, or set volume_radius\n", transfer.name,
                 radius.reason);
    prt::TransferSettings object_settings = settings_;
    object_settings.volume_radius = radius.radii;
    transfer.field.bands = settings_.bands;
    transfer.field.grid = prt::transfer_grid(transfer.bounds, object_settings);
    objects_.push_back(std::move(transfer));
  }
}

void PrtMethod::prepare(const PrepareContext& context, const ParamSet& build) {
  plan(context, build);
  Progress progress("prt source directions", static_cast<double>(objects_.size() * settings_.source_directions));
  size_t done_before = 0;
  for (ObjectTransfer& transfer : objects_) {
    const Scene alone = build_space_scene(context.scene, transfer.object);
    prt::TransferSettings object_settings = settings_;
    object_settings.volume_radius = transfer.volume_radius;
    transfer.field = prt::precompute_transfer(alone, 0, transfer.bounds, object_settings, [&](size_t done, size_t) {
      progress.update(static_cast<double>(done_before + done), transfer.name);
    });
    done_before += static_cast<size_t>(settings_.source_directions);
    transfer.response = prt::response_harmonics(transfer.field.direction_response);
  }
  progress.finish();
  ++builds_;
}

void PrtMethod::update(const FrameContext& frame, const ParamSet& frame_knobs) {
  const auto start = std::chrono::steady_clock::now();
  const HarmonicWindow window = harmonic_window(frame_knobs.text("window"));
  device_frame_ = frame_knobs.has("backend") && frame_knobs.text("backend") == "vulkan";
  for (ObjectTransfer& transfer : objects_) {
    transfer.map = build_space_map(scene_->objects[transfer.object], frame.frame.frame);
    const prt::FrameLighting lighting = projector_->project(frame.frame.lights, transfer.map, transfer.bounds.center, window);
    transfer.quadrature_points = lighting.quadrature_points;
    transfer.lighting.clear();
    for (int c = 0; c < 3; ++c)
      for (double value : lighting.coefficients[c]) transfer.lighting.push_back(static_cast<float>(value));
    if (device_frame_) {
      std::vector<float>().swap(transfer.incident);
    } else {
      transfer.incident = prt::incident_field(transfer.field, transfer.lighting);
    }
  }
  if (device_frame_) update_on_device();
  update_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

Image PrtMethod::render(const GBuffer& gbuffer, const ParamSet&) {
  if (device_frame_) return render_on_device(gbuffer);
  Image result(gbuffer.width, gbuffer.height, 3);
  std::vector<double> evaluated((gbuffer.pixel_count() + 1023) / 1024, 0.0);
  parallel_blocks(gbuffer.pixel_count(), 1024, [&](size_t begin, size_t end, size_t block) {
    for (size_t pixel = begin; pixel < end; ++pixel) {
      if (!gbuffer.receiver[pixel]) continue;
      Color irradiance(0.0f);
      for (const ObjectTransfer& transfer : objects_) {
        const Vec3 point = transfer.map.point(gbuffer.position[pixel]);
        const Vec3 normal = glm::normalize(transfer.map.normals * gbuffer.normal[pixel]);
        irradiance += prt::transfer_irradiance(transfer.field, transfer.incident, point, normal);
        evaluated[block] += 1.0;
      }
      result.set_rgb(pixel, irradiance);
    }
  });
  points_evaluated_ = 0.0;
  for (double count : evaluated) points_evaluated_ += count;
  return result;
}

size_t PrtMethod::memory_bytes() const {
  size_t bytes = 0;
  for (const ObjectTransfer& transfer : objects_)
    bytes += transfer.field.stored_bytes() + transfer.field.grid->points() * transfer.field.incident_stride() * sizeof(float);
  return bytes;
}

Counters PrtMethod::counters() const {
  double cells = 0.0, photons = 0.0, seconds = 0.0;
  for (const ObjectTransfer& transfer : objects_) {
    cells += static_cast<double>(transfer.field.grid->points());
    photons += static_cast<double>(transfer.field.stats.emitted);
    seconds += transfer.field.shoot_seconds;
  }
  return {{"cells", cells},
          {"photons_emitted", photons},
          {"precompute_seconds", seconds},
          {"bytes_per_cell", static_cast<double>(3 * settings_.bands * settings_.bands * settings_.bands * settings_.bands *
                                                 (settings_.half ? sizeof(uint16_t) : sizeof(float)))},
          {"receiver_points", points_evaluated_}};
}

nlohmann::json PrtMethod::record() const {
  nlohmann::json objects = nlohmann::json::array();
  for (const ObjectTransfer& transfer : objects_) {
    objects.push_back({{"object", transfer.name},
                       {"cells", transfer.field.grid->points()},
                       {"coefficients", transfer.field.coefficients()},
                       {"memory_bytes", transfer.field.stored_bytes()},
                       {"precision", settings_.half ? "float16" : "float32"},
                       {"volume_radius", transfer.field.grid->radius()},
                       {"volume_radius_bounding_radii", transfer.volume_radius},
                       {"volume_radius_why", transfer.volume_radius_reason},
                       {"source_directions", settings_.source_directions},
                       {"precompute_seconds", transfer.field.shoot_seconds},
                       {"environment_points_projected", transfer.quadrature_points}});
    if (transfer.response)
      objects.back()["band_limit"] = {{"full_fluence", transfer.band_energy.full},
                                      {"band_limited_fluence", transfer.band_energy.band_limited},
                                      {"change", transfer.band_energy.change()},
                                      {"response_top_band_share", transfer.response->top_band_share}};
  }
  return {{"objects", objects},
          {"update_seconds", update_seconds_},
          {"lost_beyond_ball", lost_beyond_ball_},
          {"lost_to_band_limit", band_limit_known_ ? nlohmann::json(lost_to_band_limit_) : nlohmann::json(nullptr)}};
}

// Probe photons from this frame's lights at each object, through the whole scene: the flux of the
// objects' caustics that first lands beyond the ball its grid covers, which the field does not hold. Then
// per object the fluence the band limit loses: the frame's lighting projected unwindowed to as many bands
// as the build's response resolves, against the lighting the product used (band_limit.h).
std::optional<LostFlux> PrtMethod::lost_flux(const FrameContext& frame, const GBuffer&, const ParamSet&) {
  BallLoss loss;
  for (const ObjectTransfer& transfer : objects_)
    loss.add(frame.frame, frame.tracer, transfer.object, transfer.bounds, transfer.volume_radius);
  const double needed = loss.needed;
  lost_beyond_ball_ = loss.fraction();
  double full = 0.0, band_limited = 0.0;
  band_limit_known_ = !objects_.empty();
  for (ObjectTransfer& transfer : objects_) {
    if (!transfer.response || transfer.lighting.empty() || transfer.response->bands <= settings_.bands) {
      band_limit_known_ = false;
      continue;
    }
    const BuildSpaceMap map = build_space_map(scene_->objects[transfer.object], frame.frame.frame);
    const prt::FrameLighting lighting =
        full_projector_->project(frame.frame.lights, map, transfer.bounds.center, HarmonicWindow::none);
    transfer.band_energy = prt::band_limit_energy(*transfer.response, settings_.bands, transfer.lighting, lighting.coefficients);
    full += transfer.band_energy.full;
    band_limited += transfer.band_energy.band_limited;
  }
  lost_to_band_limit_ = band_limit_known_ && full > 0.0 ? std::max(0.0, (full - band_limited) / full) : 0.0;
  LostFlux lost;
  lost.fraction = 1.0 - (1.0 - lost_beyond_ball_) * (1.0 - lost_to_band_limit_);
  lost.what = fmt::format("caustic flux whose first receiver hit lies outside the transfer grid's ball ({:.3g} %), and "
                          "the fluence in the grid the band limit loses ({})",
                          100.0 * lost_beyond_ball_,
                          band_limit_known_ ? fmt::format("{:.3g} %", 100.0 * lost_to_band_limit_)
                          : objects_.empty() || objects_.front().response
                              ? fmt::format("unknown: {} source directions resolve the response to {} bands, no more "
                                            "than sh_order",
                                            settings_.source_directions, prt::response_bands(settings_.source_directions))
                              : std::string("unknown: a build stored before it was measured"));
  const double cap = ball_radius_cap(settings_.grid_resolution);
  if (lost_to_band_limit_ > lost_beyond_ball_) {
    lost.knob = "sh_order";
    lost.advice = settings_.bands < kMaxBands
                      ? fmt::format("raise sh_order (now {}): the lighting's bands beyond it carry light the object "
                                    "sends into the grid",
                                    settings_.bands)
                      : std::string("sh_order is at its largest: the lighting is sharper than prt can hold");
  } else {
    lost.knob = "volume_radius";
    lost.advice = settings_.volume_radius > 0.0
                      ? fmt::format("set volume_radius: auto (this frame needs about {:.3g} bounding radii)", needed)
                      : fmt::format("the receivers lie beyond {:.3g} bounding radii, the largest ball auto chooses at "
                                    "this grid_resolution; raise it or set volume_radius (needs about {:.3g})",
                                    cap, needed);
  }
  return lost;
}

}  // namespace causticbench
