// One light and one specular object of caustics mapping: photon buffer, the way out of the object,
// receiver search, caustic map; and the lookup that reads it.
#include "methods/caustic_mapping/light_pass.h"

#include <algorithm>
#include <cmath>

#include "core/optics.h"
#include "core/parallel.h"
#include "methods/caustic_mapping/pass_parts.h"

namespace causticbench::caustic_mapping {

namespace {

// A point light sees its object's photon buffer under at most this half-angle (a light inside or at the
// object's bounding sphere): a perspective window cannot reach 90 degrees.
constexpr double kWidestHalfAngle = 80.0 * kPiDouble / 180.0;
// The receiver window's margin around the probed hits and the object (a fraction of its half-size), and
// the probe's texels a side: the receivers the object can light, found with exact rays, as the window
// the paper fitted by hand.
constexpr double kWindowMargin = 0.1;
constexpr int kProbeSide = 32;

// One texel of the photon buffer: the object's front surface seen from the light and, for
// two_interface, its back surface along the same ray (the back faces the paper renders).
struct PhotonTexel {
  bool covered = false;
  bool has_back = false;
  Vec3 front{0.0f}, front_normal{0.0f}, back{0.0f}, back_normal{0.0f}, travel{0.0f};
  // Through the object along the inward normal from the front (Wyman's d_N, which he precomputes per
  // vertex; here a ray per texel); 0 where there is no back.
  float normal_depth = 0.0f;
  Color flux{0.0f};  // the light's flux through the texel
};

// Texel (x, y) of the photon buffer over the plan's view, traced as a rasteriser renders it: one ray
// through the texel's centre.
PhotonTexel trace_photon_texel(const Tracer& tracer, const PassPlan& plan, int object, int resolution, int x, int y) {
  PhotonTexel texel;
  const LightView& view = plan.photon_view;
  const Ray ray = view.ray((x + 0.5) / resolution, (y + 0.5) / resolution, plan.back);
  SurfaceHit hit;
  // Anything else first is an occluder between the light and the object: no photon (the depth test
  // of the rasterised buffer).
  if (!tracer.intersect(ray, hit) || hit.object != object) return texel;
  texel.covered = true;
  texel.front = hit.position;
  texel.front_normal = hit.shading_normal;
  texel.travel = ray.direction;
  texel.flux = plan.strength * static_cast<float>(view.texel_measure(x, y, resolution));
  if (!plan.want_back) return texel;
  SurfaceHit across;
  if (tracer.intersect(tracer.spawn(hit, -hit.shading_normal), across) && across.object == object)
    texel.normal_depth = glm::length(across.position - hit.position);
  // The nearest back face along the light: what a depth-tested back-face pass keeps (on a concave
  // object, the first exit, not the last).
  SurfaceHit exit;
  if (tracer.intersect(tracer.spawn(hit, ray.direction), exit) && exit.object == object) {
    texel.has_back = true;
    texel.back = exit.position;
    texel.back_normal = exit.shading_normal;
  }
  return texel;
}

std::vector<PhotonTexel> render_photon_buffer(const Tracer& tracer, const PassPlan& plan, int object, int resolution) {
  std::vector<PhotonTexel> buffer(static_cast<size_t>(resolution) * resolution);
  parallel_blocks(buffer.size(), 1024, [&](size_t begin, size_t end, size_t) {
    for (size_t texel = begin; texel < end; ++texel)
      buffer[texel] = trace_photon_texel(tracer, plan, object, resolution, static_cast<int>(texel % resolution),
                                         static_cast<int>(texel / resolution));
  });
  return buffer;
}

// How the photon of texel `at` leaves the object: reflected off a mirror, or refracted through glass at
// one interface or, with two_interface, out of the back by Wyman's image-space approximation (the
// distance inside from the front and back depths along the light, the exit normal read where the
// refracted ray has travelled that far: `texel_at(index)` is the buffer's texel there).
template <class TexelAt>
Outgoing leave_object(const PhotonTexel& at, TexelAt&& texel_at, const LightView& view, int resolution,
                      const Material& material, const Settings& settings) {
  Outgoing out;
  if (!at.covered) return out;
  out.covered = true;
  const Vec3 travel = at.travel;
  const Vec3 normal = glm::dot(travel, at.front_normal) < 0.0f ? at.front_normal : -at.front_normal;
  const float cos_incident = std::max(0.0f, -glm::dot(travel, normal));
  out.origin = at.front;
  if (material.kind != MaterialKind::glass) {
    out.flux = at.flux * material.mirror_reflectance(cos_incident);
    out.direction = reflect(travel, normal);
    return out;
  }
  // From outside, unless the light is inside the object (a point light in the glass).
  const float eta = glm::dot(travel, at.front_normal) < 0.0f ? material.ior : 1.0f / material.ior;
  const float entering = fresnel_dielectric(cos_incident, eta);
  out.not_modelled = luminance(at.flux) * entering;
  Vec3 inside;
  if (!refract(travel, normal, eta, inside)) {  // total internal reflection (a light inside), or rounding
    out.second_failed = true;
    out.flux = at.flux * (1.0f - entering);
    return out;
  }
  out.flux = at.flux * (1.0f - entering);
  const bool one = settings.refraction == Settings::Refraction::one_interface ||
                   (settings.refraction == Settings::Refraction::automatic && !at.has_back);
  if (one) {
    out.one_interface = true;
    out.direction = inside;
    out.absorption = material.absorption;
    return out;
  }
  // Wyman 2005: the distance through the object along the light (d_V: its back depth less its front
  // depth) and along the inward normal (d_N), blended by the angles, d = (t / i) d_V + (1 - t / i) d_N
  // (exact through a sphere's centre, where the ray bends least; near a silhouette d_V alone tends to 0
  // while the ray crosses most of the object), stepped along the refracted ray; the back face's normal
  // looked up where that point projects.
  auto failed = [&] {
    out.second_failed = true;
    return out;
  };
  if (!at.has_back) return failed();
  const std::optional<LightView::Projected> front = view.project(at.front);
  const std::optional<LightView::Projected> back = view.project(at.back);
  if (!front || !back) return failed();
  const float along_light = static_cast<float>(back->depth - front->depth);
  const double incident = std::acos(std::clamp(static_cast<double>(cos_incident), 0.0, 1.0));
  const double transmitted = std::acos(std::clamp(static_cast<double>(-glm::dot(inside, normal)), 0.0, 1.0));
  const double ratio = incident > 1e-4 ? transmitted / incident : 1.0 / material.ior;
  const float distance = static_cast<float>(ratio * along_light + (1.0 - ratio) * at.normal_depth);
  const Vec3 exit = out.origin + inside * distance;
  const std::optional<LightView::Projected> exit_at = view.project(exit);
  if (!exit_at || exit_at->s < 0.0 || exit_at->s >= 1.0 || exit_at->t < 0.0 || exit_at->t >= 1.0) return failed();
  const int n = resolution;
  const size_t exit_texel = static_cast<size_t>(std::min(n - 1, static_cast<int>(exit_at->t * n))) * n +
                            static_cast<size_t>(std::min(n - 1, static_cast<int>(exit_at->s * n)));
  const PhotonTexel exit_side = texel_at(exit_texel);
  if (!exit_side.has_back) return failed();
  const Vec3 back_normal = exit_side.back_normal;
  const Vec3 facing = glm::dot(inside, back_normal) < 0.0f ? back_normal : -back_normal;
  const float cos_inside = std::max(0.0f, -glm::dot(inside, facing));
  const float leaving = fresnel_dielectric(cos_inside, 1.0f / material.ior);
  const Color through = out.flux * glm::exp(-material.absorption * distance);
  Vec3 outside;
  if (!refract(inside, facing, 1.0f / material.ior, outside)) {  // total internal reflection
    out.flux = through;  // what reaches the exit is what is lost there
    return failed();
  }
  out.not_modelled += luminance(through) * leaving;
  out.flux = through * (1.0f - leaving);
  out.origin = exit;
  out.direction = outside;
  return out;
}


}  // namespace

Settings Settings::from(const ParamSet& knobs) {
  Settings settings;
  settings.photon_resolution = static_cast<int>(knobs.integer("photon_resolution"));
  settings.map_resolution = static_cast<int>(knobs.integer("caustic_map_resolution"));
  settings.exact = knobs.text("intersection") == "exact";
  if (knobs.has("search_iterations")) settings.search_iterations = static_cast<int>(knobs.integer("search_iterations"));
  if (knobs.has("hit_position")) settings.refine = knobs.text("hit_position") == "plane";
  const std::string& refraction = knobs.text("refraction");
  settings.refraction = refraction == "two_interface"   ? Settings::Refraction::two_interface
                        : refraction == "one_interface" ? Settings::Refraction::one_interface
                                                        : Settings::Refraction::automatic;
  const std::string& splat = knobs.text("splat");
  settings.splat = splat == "point" ? SplatKind::point : splat == "gaussian" ? SplatKind::gaussian : SplatKind::variable;
  if (knobs.has("splat_radius")) settings.splat_radius = knobs.real("splat_radius");
  if (knobs.has("splat_photons")) settings.splat_photons = knobs.real("splat_photons");
  if (knobs.has("max_splat_radius")) settings.max_splat_radius = knobs.real("max_splat_radius");
  return settings;
}

void PassStatistics::add(const PassStatistics& other) {
  photons += other.photons;
  landed += other.landed;
  search_failed += other.search_failed;
  search_failed_at_start += other.search_failed_at_start;
  second_interface_failed += other.second_interface_failed;
  outside_map += other.outside_map;
  one_interface += other.one_interface;
  flux_leaving += other.flux_leaving;
  flux_search_failed += other.flux_search_failed;
  flux_search_failed_at_start += other.flux_search_failed_at_start;
  flux_second_interface += other.flux_second_interface;
  flux_outside_map += other.flux_outside_map;
  flux_not_modelled += other.flux_not_modelled;
  flux_outside_window += other.flux_outside_window;
  search_steps += other.search_steps;
}

PassPlan plan_pass(const Tracer& tracer, const LightFrame& light, int object, const Settings& settings) {
  PassPlan plan;
  const SceneFrame& frame = tracer.frame();
  const BoundingSphere& bounds = frame.bounds[static_cast<size_t>(object)];
  const Material& material = frame.scene->objects[static_cast<size_t>(object)].material;
  const std::optional<LightView> view = light_view_of(light, bounds, kWidestHalfAngle);
  if (!view) return plan;
  plan.valid = true;
  plan.photon_view = *view;
  plan.strength = light.kind == LightKind::directional ? light.light->irradiance : light.light->intensity;
  plan.want_back = material.kind == MaterialKind::glass && settings.refraction != Settings::Refraction::one_interface;
  if (light.kind == LightKind::point) {
    // The solid angle of the bounding sphere's cone from the light (all of it from inside) against the
    // window's square, 4 atan(h^2 / sqrt(1 + 2 h^2)): nonzero only where the window was capped.
    const double distance = glm::length(glm::dvec3(bounds.center) - glm::dvec3(light.position));
    const double ratio = bounds.radius / std::max(distance, 1e-30);
    const double cone = ratio < 1.0 ? 2.0 * kPiDouble * (1.0 - std::sqrt(1.0 - ratio * ratio)) : 4.0 * kPiDouble;
    const double h = view->half_extent();
    const double window = 4.0 * std::atan(h * h / std::sqrt(1.0 + 2.0 * h * h));
    if (cone > window * 1.0001) plan.flux_outside_window = luminance(light.light->intensity) * (cone - window);
  }
  // Orthographic rays start outside the whole scene.
  plan.back = glm::length(bounds.center - frame.scene_bounds.center) + frame.scene_bounds.radius + bounds.radius;

  // The receiver window: the object's own silhouette (the search starts from the receiver behind a
  // photon's texel), where a probe of photons meets the receivers with exact rays, and the search's first
  // step (the start's distance along the ray), which overshoots the hit where the receiver behind the
  // photon lies farther than the one its ray meets and must still read the map. The probe's photons are
  // texels of the full photon buffer, traced on their own (and the texels their second interfaces read).
  std::vector<Vec3> points;
  for (int corner = 0; corner < 8; ++corner)
    points.push_back(bounds.center + bounds.radius * Vec3(corner & 1 ? 1 : -1, corner & 2 ? 1 : -1, corner & 4 ? 1 : -1));
  const int n = settings.photon_resolution;
  const int stride = std::max(1, n / kProbeSide);
  std::vector<int> probes;
  for (int y = stride / 2; y < n; y += stride)
    for (int x = stride / 2; x < n; x += stride) probes.push_back(y * n + x);
  std::vector<std::vector<Vec3>> found(probes.size());
  ReceiverMap none;
  none.object = object;
  const auto texel_at = [&](size_t texel) {
    return trace_photon_texel(tracer, plan, object, n, static_cast<int>(texel % n), static_cast<int>(texel / n));
  };
  parallel_blocks(probes.size(), 16, [&](size_t begin, size_t end, size_t) {
    for (size_t i = begin; i < end; ++i) {
      const Outgoing photon = leave_object(texel_at(static_cast<size_t>(probes[i])), texel_at, *view, n, material, settings);
      if (!photon.covered || photon.second_failed) continue;
      const SearchResult probe = search_receiver(none, tracer, photon.origin, photon.direction, 0, true);
      if (probe.failure != SearchFailure::none) continue;  // leaves the scene: no receiver to hold
      found[i].push_back(probe.hit);
      SurfaceHit behind;
      const Vec3 travel = view->travel_at(photon.origin);
      if (first_receiver(tracer, Ray{photon.origin + travel * tracer.epsilon(), travel}, behind, object))
        found[i].push_back(photon.origin + photon.direction * glm::length(behind.position - photon.origin));
    }
  });
  for (const std::vector<Vec3>& probe : found) points.insert(points.end(), probe.begin(), probe.end());
  plan.receiver_view = LightView::fitted(*view, points, kWindowMargin, std::tan(kWidestHalfAngle)).value_or(*view);
  return plan;
}

LightPass planned_pass(const Tracer& tracer, const LightFrame& light, int object, const Settings& settings) {
  LightPass pass;
  pass.object = object;
  pass.light_name = light.light ? light.light->name : "";
  pass.plan = plan_pass(tracer, light, object, settings);
  if (!pass.plan.valid) return pass;
  pass.photon_window_half_extent = pass.plan.photon_view.half_extent();
  pass.statistics.flux_outside_window = pass.plan.flux_outside_window;
  pass.statistics.flux_leaving += pass.plan.flux_outside_window;
  pass.receivers.view = pass.plan.receiver_view;
  pass.receivers.object = object;
  pass.receivers.resolution = settings.map_resolution;
  return pass;
}

void count_leaving(LightPass& pass, const Outgoing& photon) {
  if (!photon.covered) return;
  PassStatistics& statistics = pass.statistics;
  ++statistics.photons;
  statistics.one_interface += photon.one_interface;
  const double flux = luminance(photon.flux);
  statistics.flux_leaving += flux + photon.not_modelled;
  statistics.flux_not_modelled += photon.not_modelled;
  if (photon.second_failed) {
    ++statistics.second_interface_failed;
    statistics.flux_second_interface += flux;
    return;
  }
  pass.leaving.push_back(PhotonRay{photon.origin, photon.direction, photon.flux, photon.absorption});
}

LightPass begin_pass(const Tracer& tracer, const LightFrame& light, int object, const Settings& settings) {
  LightPass pass = planned_pass(tracer, light, object, settings);
  if (!pass.plan.valid) return pass;
  const Material& material = tracer.frame().scene->objects[static_cast<size_t>(object)].material;
  // The photon buffer and each photon's way out of the object.
  const int n = settings.photon_resolution;
  const std::vector<PhotonTexel> buffer = render_photon_buffer(tracer, pass.plan, object, n);
  std::vector<Outgoing> outgoing(buffer.size());
  const auto texel_at = [&](size_t texel) -> const PhotonTexel& { return buffer[texel]; };
  parallel_blocks(buffer.size(), 1024, [&](size_t begin, size_t end, size_t) {
    for (size_t texel = begin; texel < end; ++texel)
      outgoing[texel] = leave_object(buffer[texel], texel_at, pass.plan.photon_view, n, material, settings);
  });
  pass.leaving.reserve(static_cast<size_t>(
      std::count_if(outgoing.begin(), outgoing.end(), [](const Outgoing& photon) { return photon.covered && !photon.second_failed; })));
  for (const Outgoing& photon : outgoing) count_leaving(pass, photon);
  pass.receivers = render_receiver_map(tracer, pass.plan.receiver_view, settings.map_resolution, pass.plan.back, object);
  return pass;
}

void count_landing(PassStatistics& statistics, const PhotonRay& photon, Landing landing, const Color& arriving, int steps,
                   bool at_start) {
  statistics.search_steps += static_cast<uint64_t>(steps);
  const double flux = luminance(photon.flux);
  if (landing == Landing::search_failed) {
    ++statistics.search_failed;
    statistics.flux_search_failed += flux;
    if (at_start) {  // the start's read failed: there was nothing to iterate from
      ++statistics.search_failed_at_start;
      statistics.flux_search_failed_at_start += flux;
    }
    return;
  }
  // Absorbed on the way is light the reference absorbs too: neither landed nor lost.
  statistics.flux_leaving -= flux - luminance(arriving);
  if (landing == Landing::outside_map) {
    ++statistics.outside_map;
    statistics.flux_outside_map += luminance(arriving);
    return;
  }
  ++statistics.landed;
}

void land_and_splat(const Tracer& tracer, const Settings& settings, LightPass& pass) {
  if (pass.receivers.resolution == 0) return;  // no light view
  // Each photon's receiver, in blocks whose statistics add in block order.
  const size_t count = pass.leaving.size(), block = 4096, blocks = (count + block - 1) / block;
  std::vector<std::vector<LandedPhoton>> landed(blocks);
  std::vector<std::vector<uint32_t>> dropped(blocks);
  std::vector<std::vector<uint8_t>> dropped_at_start(blocks);
  std::vector<PassStatistics> block_statistics(blocks);
  const int n = settings.map_resolution;
  const ReceiverMap& receivers = pass.receivers;
  parallel_blocks(count, block, [&](size_t begin, size_t end, size_t index) {
    PassStatistics& statistics = block_statistics[index];
    for (size_t i = begin; i < end; ++i) {
      const PhotonRay& photon = pass.leaving[i];
      const SearchResult found = search_receiver(receivers, tracer, photon.origin, photon.direction,
                                                 settings.search_iterations, settings.exact, settings.refine);
      if (found.failure != SearchFailure::none) {
        // Failed at the start: the first read found nothing (an exact ray is no search; a search that read
        // once and did not converge had a start).
        const bool at_start = !settings.exact && found.steps == 1 && found.failure != SearchFailure::not_converged;
        count_landing(statistics, photon, Landing::search_failed, Color(0.0f), found.steps, at_start);
        dropped[index].push_back(static_cast<uint32_t>(i));
        dropped_at_start[index].push_back(at_start ? 1 : 0);
        continue;
      }
      const Color arriving = photon.flux * glm::exp(-photon.absorption * glm::length(found.hit - photon.origin));
      // The caustic map holds light on what the light sees: a hit outside its window, or on a surface hidden
      // from the light (a wall's far side: exact rays find such hits), has no texel of its own.
      const std::optional<LightView::Projected> at = receivers.view.project(found.hit);
      const long map_texel = at ? receivers.texel(at->s, at->t) : -1;
      if (map_texel < 0 ||
          !receivers.sees(*at, map_texel, found.hit, receivers.normal[static_cast<size_t>(map_texel)])) {
        count_landing(statistics, photon, Landing::outside_map, arriving, found.steps);
        continue;
      }
      count_landing(statistics, photon, Landing::landed, arriving, found.steps);
      landed[index].push_back(LandedPhoton{static_cast<float>(at->s * n), static_cast<float>(at->t * n), arriving});
    }
  });
  std::vector<LandedPhoton> photons;
  for (size_t index = 0; index < blocks; ++index) {
    pass.statistics.add(block_statistics[index]);
    photons.insert(photons.end(), landed[index].begin(), landed[index].end());
    pass.dropped.insert(pass.dropped.end(), dropped[index].begin(), dropped[index].end());
    pass.dropped_at_start.insert(pass.dropped_at_start.end(), dropped_at_start[index].begin(), dropped_at_start[index].end());
  }

  // The caustic map, as flux per texel measure.
  std::vector<double> flux;
  splat_photons(photons, settings, n, flux);
  pass.density.assign(flux.size(), 0.0f);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const double measure = receivers.view.texel_measure(x, y, n);
      if (!(measure > 0.0)) continue;  // a degenerate window: no area to spread flux over
      const size_t texel = static_cast<size_t>(y) * n + x;
      for (int c = 0; c < 3; ++c) pass.density[texel * 3 + c] = static_cast<float>(flux[texel * 3 + c] / measure);
    }
}

LightPass run_pass(const Tracer& tracer, const LightFrame& light, int object, const Settings& settings) {
  LightPass pass = begin_pass(tracer, light, object, settings);
  land_and_splat(tracer, settings, pass);
  return pass;
}

void add_lookup(const LightPass& pass, const Vec3& point, const Vec3& normal, Color& irradiance) {
  const ReceiverMap& map = pass.receivers;
  if (pass.density.empty()) return;
  const std::optional<LightView::Projected> at = map.view.project(point);
  if (!at) return;
  const long texel = map.texel(at->s, at->t);
  if (texel < 0 || !std::isfinite(map.depth[static_cast<size_t>(texel)])) return;
  if (!map.sees(*at, texel, point, normal)) return;
  const double cosine = std::abs(glm::dot(normal, map.view.travel_at(point)));
  // Bilinear over the density (texel centres at half-integers), clamped at the window's edge.
  const int n = map.resolution;
  const double fx = std::clamp(at->s * n - 0.5, 0.0, n - 1.0), fy = std::clamp(at->t * n - 0.5, 0.0, n - 1.0);
  const int x0 = std::min(static_cast<int>(fx), n - 2 < 0 ? 0 : n - 2), y0 = std::min(static_cast<int>(fy), n - 2 < 0 ? 0 : n - 2);
  const int x1 = std::min(x0 + 1, n - 1), y1 = std::min(y0 + 1, n - 1);
  const double wx = fx - x0, wy = fy - y0;
  Color density(0.0f);
  auto tap = [&](int x, int y, double w) {
    const size_t i = (static_cast<size_t>(y) * n + x) * 3;
    density += Color(pass.density[i], pass.density[i + 1], pass.density[i + 2]) * static_cast<float>(w);
  };
  tap(x0, y0, (1 - wx) * (1 - wy));
  tap(x1, y0, wx * (1 - wy));
  tap(x0, y1, (1 - wx) * wy);
  tap(x1, y1, wx * wy);
  // Flux per area across the light times the cosine is irradiance on the surface (directional); from a
  // point light, flux per steradian times the cosine over the distance squared.
  const double scale = map.view.is_orthographic() ? cosine : cosine / (at->depth * at->depth);
  irradiance += density * static_cast<float>(scale);
}

}  // namespace causticbench::caustic_mapping
