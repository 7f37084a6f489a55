// caustic_volume's lifecycle: the frame's volumes in update(), their footprints on the image, what they
// lose; the per-pixel work is in caustic_volume_render.cpp, one volume in volume.h.
#include "methods/caustic_volume/caustic_volume.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "core/errors.h"
#include "core/parallel.h"
#include "methods/common/receivers.h"

namespace causticbench {

using caustic_volume::Volume;

void CausticVolumeMethod::check_scene(const Scene& scene) const {
  require_specular_object(scene, "caustic_volume builds volumes on the specular objects' triangles");
}

namespace {

// The convex hull of `points`, counter-clockwise (Andrew's monotone chain).
std::vector<glm::dvec2> convex_hull(std::vector<glm::dvec2> points) {
  std::sort(points.begin(), points.end(), [](const glm::dvec2& a, const glm::dvec2& b) {
    return a.x < b.x || (a.x == b.x && a.y < b.y);
  });
  auto turn = [](const glm::dvec2& o, const glm::dvec2& a, const glm::dvec2& b) {
    return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
  };
  std::vector<glm::dvec2> hull(2 * points.size());
  size_t k = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    while (k >= 2 && turn(hull[k - 2], hull[k - 1], points[i]) <= 0.0) --k;
    hull[k++] = points[i];
  }
  for (size_t i = points.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && turn(hull[k - 2], hull[k - 1], points[i]) <= 0.0) --k;
    hull[k++] = points[i];
  }
  hull.resize(k > 1 ? k - 1 : k);
  return hull;
}

CausticVolumeMethod::Footprint footprint_of(const Volume& volume, const CameraFrame& camera) {
  CausticVolumeMethod::Footprint footprint;
  std::vector<glm::dvec2> corners;
  for (int i = 0; i < 3; ++i)
    for (double t : {0.0, volume.t_max}) {
      const std::optional<glm::dvec2> at = camera.image_position(Vec3(volume.origin[i] + t * volume.direction[i]));
      if (!at || !std::isfinite(at->x) || !std::isfinite(at->y)) {
        footprint.whole_image = true;
        footprint.row_begin = 0;
        footprint.row_end = camera.height();
        return footprint;
      }
      corners.push_back(*at);
    }
  footprint.hull = convex_hull(corners);
  double low = corners[0].y, high = corners[0].y;
  for (const glm::dvec2& corner : corners) low = std::min(low, corner.y), high = std::max(high, corner.y);
  // A pixel's point is tested when its centre lies within a pixel of the hull (the points lie on the
  // primary rays through the centres; the pixel keeps rounding out of the decision).
  footprint.row_begin = std::clamp(static_cast<int>(std::floor(low - 1.5)), 0, camera.height());
  footprint.row_end = std::clamp(static_cast<int>(std::ceil(high + 1.5)), 0, camera.height());
  return footprint;
}

}  // namespace

void CausticVolumeMethod::update(const FrameContext& frame, const ParamSet& frame_knobs) {
  ++update_count_;
  volumes_.clear();
  footprints_.clear();
  statistics_ = caustic_volume::BeamStatistics{};
  skipped_lights_.clear();
  tessellation_ = static_cast<int>(frame_knobs.integer("tessellation"));
  const std::string& refraction_name = frame_knobs.has("refraction") ? frame_knobs.text("refraction") : "auto";
  const caustic_volume::Refraction refraction = refraction_name == "one_interface"    ? caustic_volume::Refraction::one_interface
                                                : refraction_name == "through_object" ? caustic_volume::Refraction::through_object
                                                                                      : caustic_volume::Refraction::automatic;
  tracer_ = &frame.tracer;
  const SceneFrame& scene = frame.frame;
  camera_ = scene.camera;
  const std::vector<int> objects = scene.specular_objects();
  const bool automatic = frame_knobs.is_auto("max_distance");
  const caustic_volume::ReceiverBox box = caustic_volume::receiver_box(scene);
  t_max_used_ = 0.0;
  for (const LightFrame& light : scene.lights) {
    // An environment or a spot has no one direction per vertex here: not modelled, and said in the record.
    if (light.kind != LightKind::directional && light.kind != LightKind::point) {
      skipped_lights_.push_back(light.light->name);
      continue;
    }
    for (int object : objects) {
      const BoundingSphere& bounds = scene.bounds[static_cast<size_t>(object)];
      // auto: every receiver of the scene lies within this distance of every point of the object, and
      // each volume stops where all its rays have left the receivers' box (volume.h, box_cap).
      const double t_max = automatic ? glm::length(glm::dvec3(bounds.center) - glm::dvec3(scene.scene_bounds.center)) +
                                           scene.scene_bounds.radius + bounds.radius
                                     : frame_knobs.real("max_distance");
      const SurfaceMesh mesh = surface_mesh(scene, object, tessellation_, /*subdivide_flat_solids=*/true);
      caustic_volume::build_volumes(frame.tracer, light, mesh, object, scene.scene->objects[static_cast<size_t>(object)].material,
                                    refraction, t_max, automatic && !box.empty ? &box : nullptr, volumes_, statistics_);
    }
  }
  for (const Volume& volume : volumes_) t_max_used_ = std::max(t_max_used_, volume.t_max);
  footprints_.resize(volumes_.size());
  parallel_blocks(volumes_.size(), 256, [&](size_t begin, size_t end, size_t) {
    for (size_t i = begin; i < end; ++i) footprints_[i] = footprint_of(volumes_[i], *camera_);
  });
}

size_t CausticVolumeMethod::memory_bytes() const {
  size_t bytes = volumes_.size() * (sizeof(Volume) + sizeof(Footprint));
  for (const Footprint& footprint : footprints_) bytes += footprint.hull.size() * sizeof(glm::dvec2);
  return bytes;
}

// A volume and its footprint take about 700 bytes; a sphere's tessellation makes segments^2 triangles,
// the most of any shape (a ring's wall makes segments^2 / 4), per light and specular object.
std::vector<MemoryTerm> CausticVolumeMethod::knob_memory(const PrepareContext& context, const ParamSet& knobs) const {
  const double segments = static_cast<double>(knobs.integer("tessellation"));
  size_t lights = 0;
  for (const LightFrame& light : context.rest.lights) lights += light.kind == LightKind::directional || light.kind == LightKind::point;
  const double passes = static_cast<double>(std::max<size_t>(1, lights * context.rest.specular_objects().size()));
  const double volumes = segments * segments * passes;
  return {MemoryTerm{{"tessellation"}, volumes * 700.0,
                     fmt::format("up to {:.3g} volumes ({:g}^2 triangles x {:g} light-object pairs) x about 700 bytes",
                                 volumes, segments, passes)}};
}

Counters CausticVolumeMethod::counters() const {
  return {{"volumes", static_cast<double>(volumes_.size())},
          {"volume_point_tests", static_cast<double>(point_tests_)},
          {"volume_hits", static_cast<double>(sheets_)},
          {"shadow_rays", static_cast<double>(shadow_rays_)}};
}

nlohmann::json CausticVolumeMethod::record() const {
  nlohmann::json record = {{"tessellation", tessellation_},
                           {"triangles", statistics_.triangles},
                           {"volumes", statistics_.lit},
                           {"triangles_unlit", statistics_.unlit},
                           {"volumes_dropped", statistics_.dropped},
                           {"volumes_torn", statistics_.torn},
                           {"max_distance_largest", t_max_used_}};
  if (!skipped_lights_.empty()) record["lights_not_modelled"] = skipped_lights_;
  return record;
}

namespace {

// Whether the light of the volume's cross-section point at barycentric (b0, b1, 1 - b0 - b1) meets its
// first receiver beyond the far cap. That point travels P(b) + t D(b), P and D interpolated (D not
// normalised: the volume's cross-section at t is the triangle P_i + t D_i), so its receiver lies beyond
// the cap where the hit's t exceeds t_max. Volumes ignore what lies inside them (occlusion is not
// modelled): the first receiver along the ray.
bool beyond_cap(const Tracer& tracer, const Volume& volume, double b0, double b1) {
  const double b2 = 1.0 - b0 - b1;
  const glm::dvec3 start = b0 * volume.origin[0] + b1 * volume.origin[1] + b2 * volume.origin[2];
  const glm::dvec3 travel = b0 * volume.direction[0] + b1 * volume.direction[1] + b2 * volume.direction[2];
  const double speed = glm::length(travel);
  if (!(speed > 0.0)) return false;
  const glm::dvec3 unit = travel / speed;
  SurfaceHit hit;
  if (!first_receiver(tracer, Ray{Vec3(start + unit * double(tracer.epsilon())), Vec3(unit)}, hit)) return false;
  // Within the tracer's epsilon of the cap is at it: under max_distance auto a flat receiver (a floor) lies
  // exactly on the receivers' box, where box_cap puts the cap, and the hit's float position would otherwise
  // count about half of the light landing there as beyond (glass_cube: 0.24 of its light, which the volumes
  // do deliver).
  return (glm::length(glm::dvec3(hit.position) - start) - double(tracer.epsilon())) / speed > volume.t_max;
}

// The share of a volume's light that meets its first receiver beyond the far cap, its cross-section taken
// as evenly lit: the centroid and three points near the corners first, and only where they disagree (the
// cap crosses a receiver within this volume) the centroids of the 16 x 16 sub-triangles of the triangle,
// a midpoint rule, so that a volume costs four rays unless the cap cuts it.
double share_beyond_cap(const Tracer& tracer, const Volume& volume) {
  const bool centre = beyond_cap(tracer, volume, 1.0 / 3.0, 1.0 / 3.0);
  const bool agree = beyond_cap(tracer, volume, 0.9, 0.05) == centre && beyond_cap(tracer, volume, 0.05, 0.9) == centre &&
                     beyond_cap(tracer, volume, 0.05, 0.05) == centre;
  if (agree) return centre ? 1.0 : 0.0;
  constexpr int n = 16;
  int beyond = 0;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; i + j < n; ++j) {
      beyond += beyond_cap(tracer, volume, (i + 1.0 / 3.0) / n, (j + 1.0 / 3.0) / n) ? 1 : 0;
      if (i + j < n - 1) beyond += beyond_cap(tracer, volume, (i + 2.0 / 3.0) / n, (j + 2.0 / 3.0) / n) ? 1 : 0;
    }
  }
  return static_cast<double>(beyond) / (n * n);
}

}  // namespace

// The flux entering the lit triangles that no receiver gets: volumes dropped because a vertex ray could
// not leave, and the share of each volume's light that meets its first receiver beyond the far cap
// (share_beyond_cap, untimed; tests/test_caustic_volume.cpp checks it against a closed form), all as
// flux entering the triangles (the dropped and torn volumes have no reflectance or transmittance to
// apply: their rays do not leave).
std::optional<LostFlux> CausticVolumeMethod::lost_flux(const FrameContext& frame, const GBuffer&, const ParamSet&) {
  std::vector<double> beyond(volumes_.size(), 0.0);
  parallel_blocks(volumes_.size(), 256, [&](size_t begin, size_t end, size_t) {
    for (size_t i = begin; i < end; ++i) beyond[i] = volumes_[i].flux_entering * share_beyond_cap(frame.tracer, volumes_[i]);
  });
  double flux_beyond = 0.0;
  for (double value : beyond) flux_beyond += value;
  LostFlux lost;
  lost.what = "flux entering the lit specular triangles that no receiver gets: volumes whose vertex rays cannot "
              "leave (refraction impossible at a vertex, trapped inside a solid), volumes torn through a solid (their "
              "rays left after different internal reflections), and light meeting its first receiver beyond the far cap";
  const double torn_and_dropped = statistics_.flux_dropped + statistics_.flux_torn;
  if (flux_beyond >= torn_and_dropped) {
    lost.knob = "max_distance";
    lost.advice = "set max_distance: auto, which reaches the far side of the receivers";
  } else {
    lost.knob = "tessellation";
    lost.advice = "raise tessellation: finer volumes tear along a narrower band where a solid's rays part";
  }
  const double total = statistics_.flux_lit + torn_and_dropped;
  lost.fraction = total > 0.0 ? std::clamp((torn_and_dropped + flux_beyond) / total, 0.0, 1.0) : 0.0;
  return lost;
}

}  // namespace causticbench
