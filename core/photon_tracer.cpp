#include "core/photon_tracer.h"

#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

#include <fmt/format.h>

#include "core/low_discrepancy.h"
#include "core/optics.h"
#include "core/parallel.h"

namespace causticbench {

void PhotonLights::add_directional(Vec3 direction_to_light, Color irradiance, double solid_angle_sr) {
  if (!(glm::length(direction_to_light) > 0.0f)) {
    throw std::invalid_argument("PhotonLights::add_directional: the direction to the light is zero or not finite");
  }
  if (!(solid_angle_sr >= 0.0 && solid_angle_sr <= 2.0 * kPiDouble)) {
    throw std::invalid_argument(fmt::format("PhotonLights::add_directional: solid angle {} sr is not in [0, 2 pi]",
                                            solid_angle_sr));
  }
  Light light;
  light.kind = LightKind::directional;
  light.name = "explicit directional";
  // Light::direction is the way light travels: away from the light.
  light.direction = Vec3Track::constant(-glm::dvec3(direction_to_light));
  light.irradiance = irradiance;
  light.solid_angle = solid_angle_sr;
  lights_.push_back(std::move(light));
  frames_.push_back(pose_light(lights_.back(), 0.0));
}

void PhotonLights::add_point(Vec3 position, Color intensity_w_per_sr, double radius) {
  if (!(radius >= 0.0)) {
    throw std::invalid_argument(fmt::format("PhotonLights::add_point: radius {} is negative", radius));
  }
  Light light;
  light.kind = LightKind::point;
  light.name = "explicit point";
  light.position = Vec3Track::constant(glm::dvec3(position));
  light.intensity = intensity_w_per_sr;
  light.radius = radius;
  lights_.push_back(std::move(light));
  frames_.push_back(pose_light(lights_.back(), 0.0));
}

void PhotonLights::add(const LightFrame& light) {
  if (!light.light) throw std::invalid_argument("PhotonLights::add: the light frame points at no light");
  frames_.push_back(light);
}

CausticPhotonTracer::CausticPhotonTracer(const Tracer& tracer, PhotonTracerSettings settings)
    : CausticPhotonTracer(tracer, settings, tracer.frame().lights, tracer.frame().specular_objects()) {}

CausticPhotonTracer::CausticPhotonTracer(const Tracer& tracer, PhotonTracerSettings settings,
                                         const std::vector<LightFrame>& lights, const std::vector<int>& target_objects)
    : tracer_(tracer), settings_(settings), lights_(lights) {
  const SceneFrame& frame = tracer.frame();
  std::vector<bool> chosen(frame.bounds.size(), false);
  for (int object : target_objects) {
    if (object < 0 || static_cast<size_t>(object) >= frame.bounds.size()) {
      throw std::invalid_argument(fmt::format("CausticPhotonTracer: target object {} is not in the scene (it has {})",
                                              object, frame.bounds.size()));
    }
    // A target listed twice would be aimed at twice as often; the weights would stay exact, but its
    // cross-section would count twice in target_cross_section().
    if (chosen[object]) {
      throw std::invalid_argument(fmt::format("CausticPhotonTracer: target object {} is listed twice", object));
    }
    chosen[object] = true;
    targets_.push_back(frame.bounds[object]);
    target_area_ += kPiDouble * frame.bounds[object].radius * frame.bounds[object].radius;
  }
  for (const LightFrame& light : lights_) {
    if (!light.light) throw std::invalid_argument("CausticPhotonTracer: a light frame points at no light");
  }
  // Each receiver's and each target's world box (Blocked): its analytic bounds' corners or its world mesh,
  // posed; an object with no geometry has none.
  auto box_of = [&frame](int object) {
    WorldBox box{object, Vec3(std::numeric_limits<float>::max()), Vec3(-std::numeric_limits<float>::max())};
    auto include = [&](const Vec3& p) { box.lower = glm::min(box.lower, p), box.upper = glm::max(box.upper, p); };
    const SceneObject& described = frame.scene->objects[static_cast<size_t>(object)];
    if (described.shape.is_analytic()) {
      glm::dvec3 lower, upper;
      analytic_bounds(described.shape, lower, upper);
      for (int corner = 0; corner < 8; ++corner)
        include(frame.transforms[static_cast<size_t>(object)].point(
            Vec3((corner & 1) ? upper.x : lower.x, (corner & 2) ? upper.y : lower.y, (corner & 4) ? upper.z : lower.z)));
    } else if (static_cast<size_t>(object) < frame.world_meshes.size()) {
      for (const Vec3& p : frame.world_meshes[static_cast<size_t>(object)].positions) include(p);
    }
    return box;
  };
  auto has_volume = [](const WorldBox& box) { return glm::all(glm::lessThanEqual(box.lower, box.upper)); };
  for (size_t object = 0; object < frame.scene->objects.size() && object < frame.transforms.size(); ++object) {
    if (!frame.scene->objects[object].material.receives_caustics()) continue;
    const WorldBox box = box_of(static_cast<int>(object));
    if (has_volume(box)) receivers_.push_back(box);
  }
  for (int object : target_objects) {
    if (static_cast<size_t>(object) >= frame.transforms.size()) continue;
    const WorldBox box = box_of(object);
    if (has_volume(box)) target_boxes_.push_back(box);
  }
  // Choose lights in proportion to the flux they aim at the targets (estimated from luminance).
  std::vector<double> weights;
  for (const LightFrame& light : lights_) {
    double weight = 0.0;
    switch (light.kind) {
      case LightKind::directional:
      case LightKind::gaussian_spot: weight = luminance(light.light->irradiance) * target_area_; break;
      case LightKind::environment_image:
        weight = luminance(light.light->environment->upward_irradiance()) * 2.0 * target_area_;
        break;
      case LightKind::point: {
        double solid_angle = 0.0;
        for (const BoundingSphere& target : targets_) {
          double distance = glm::length(target.center - light.position);
          double cos_max = distance > target.radius + light.radius
                               ? std::sqrt(1.0 - std::pow(target.radius / (distance - light.radius), 2.0))
                               : -1.0;
          solid_angle += 2.0 * kPiDouble * (1.0 - cos_max);
        }
        weight = luminance(light.light->intensity) * solid_angle;
        break;
      }
    }
    weights.push_back(std::max(0.0, weight));
  }
  light_choice_ = Distribution1D(weights);
  total_weight_ = light_choice_.total();
}

// Where an emission's numbers come from: the photon's own Random, drawn in call order (as emit() always
// did, so that random emission is unchanged bit for bit), or one point of a pass's shifted Sobol sequence,
// a dimension per purpose, the most telling first: `aim` (the disk across a target, or the cone towards
// it: where a caustic forms), `light_sample` (a light's own direction or position), `target`, `light`.
class CausticPhotonTracer::EmissionDraws {
 public:
  EmissionDraws(Random& random, const ShiftedSobol* sobol, uint32_t point) : random_(random), sobol_(sobol), point_(point) {}
  float aim(int axis) { return sobol_ ? sobol_->uniform(point_, axis) : random_.uniform(); }
  float light_sample(int axis) { return sobol_ ? sobol_->uniform(point_, 2 + axis) : random_.uniform(); }
  double target() { return sobol_ ? sobol_->uniform_double(point_, 5) : random_.uniform_double(); }
  double light() { return sobol_ ? sobol_->uniform_double(point_, 6) : random_.uniform_double(); }

 private:
  Random& random_;
  const ShiftedSobol* sobol_;
  uint32_t point_;
};

bool CausticPhotonTracer::emit(EmissionDraws& draws, Ray& ray, Color& power, PathLight& light_class) const {
  double light_probability;
  size_t light_index = light_choice_.sample(draws.light(), light_probability);
  const LightFrame& light = lights_[light_index];
  light_class = path_light_of(light.kind);
  // Choose a target with probability proportional to its weight, then count every target the
  // resulting ray could also have come from: the one-sample balance weight of Veach, exact for overlaps.
  if (light.kind == LightKind::point) {
    Vec3 origin = light.sample_position(draws.light_sample(0), draws.light_sample(1));
    thread_local std::vector<float> cos_max;
    cos_max.resize(targets_.size());
    double solid_angle_sum = 0.0;
    for (size_t i = 0; i < targets_.size(); ++i) {
      float distance = glm::length(targets_[i].center - origin);
      cos_max[i] = distance > targets_[i].radius
                       ? std::sqrt(std::max(0.0f, 1.0f - (targets_[i].radius / distance) * (targets_[i].radius / distance)))
                       : -1.0f;
      solid_angle_sum += 2.0 * kPiDouble * (1.0 - cos_max[i]);
    }
    double pick = draws.target() * solid_angle_sum, accumulated = 0.0;
    size_t chosen = targets_.size() - 1;
    for (size_t i = 0; i < targets_.size(); ++i) {
      accumulated += 2.0 * kPiDouble * (1.0 - cos_max[i]);
      if (pick < accumulated) {
        chosen = i;
        break;
      }
    }
    Vec3 axis = cos_max[chosen] > -1.0f ? glm::normalize(targets_[chosen].center - origin) : Vec3(0, 1, 0);
    Vec3 direction = sample_cone(axis, cos_max[chosen], draws.aim(0), draws.aim(1));
    int covering = 0;
    for (size_t i = 0; i < targets_.size(); ++i) {
      if (cos_max[i] <= -1.0f) {
        ++covering;
        continue;
      }
      Vec3 to_center = glm::normalize(targets_[i].center - origin);
      if (glm::dot(direction, to_center) >= cos_max[i]) ++covering;
    }
    covering = std::max(covering, 1);
    power = light.light->intensity * static_cast<float>(solid_angle_sum / covering / light_probability);
    ray.origin = origin;
    ray.direction = direction;
    ray.t_min = 0.0f;
    ray.t_max = 1e30f;
    return true;
  }
  Color radiance_over_pdf;
  Vec3 to_light = light.sample_direction(draws.light_sample(0), draws.light_sample(1), draws.light_sample(2), radiance_over_pdf);
  if (max_component(radiance_over_pdf) <= 0.0f) return false;
  double pick = draws.target() * target_area_, accumulated = 0.0;
  size_t chosen = targets_.size() - 1;
  for (size_t i = 0; i < targets_.size(); ++i) {
    accumulated += kPiDouble * targets_[i].radius * targets_[i].radius;
    if (pick < accumulated) {
      chosen = i;
      break;
    }
  }
  Vec3 t, b;
  orthonormal_basis(to_light, t, b);
  float x, y;
  sample_disk(draws.aim(0), draws.aim(1), x, y);
  Vec3 point = targets_[chosen].center + targets_[chosen].radius * (x * t + y * b);
  int covering = 0;
  for (const BoundingSphere& target : targets_) {
    Vec3 offset = target.center - point;
    Vec3 across = offset - glm::dot(offset, to_light) * to_light;
    if (glm::dot(across, across) <= target.radius * target.radius * 1.000001f) ++covering;
  }
  covering = std::max(covering, 1);
  const BoundingSphere& scene = tracer_.frame().scene_bounds;
  float back = glm::dot(scene.center - point, to_light) + scene.radius * 1.01f;
  ray.origin = point + to_light * back;
  ray.direction = -to_light;
  ray.t_min = 0.0f;
  ray.t_max = 1e30f;
  power = radiance_over_pdf * static_cast<float>(target_area_ / covering / light_probability);
  return true;
}

// The one path walk of a caustic photon. `on_receiver(hit, arrival_normal, direction, power, path)` is called
// where a path with at least one specular bounce meets a surface with a diffuse part (`path`: its class so
// far, PathClass::packed);
// `on_segment(segment)` for every straight piece travelled after the first specular bounce.
template <class OnReceiver, class OnSegment>
void CausticPhotonTracer::walk(uint64_t index, PhotonStats& stats, OnReceiver&& on_receiver, OnSegment&& on_segment,
                               const BlockedVisit* on_blocked) const {
  Random random(settings_.seed, index);
  ++stats.emitted;
  // Nothing to aim at, or no flux towards it: the photon counts as emitted and carries nothing.
  if (targets_.empty() || total_weight_ <= 0.0) return;
  Ray ray;
  Color power;
  std::optional<ShiftedSobol> sobol;
  uint32_t point = 0;
  if (settings_.stratified_pass_size > 0) {
    sobol.emplace(settings_.seed, index / settings_.stratified_pass_size);
    point = static_cast<uint32_t>(index % settings_.stratified_pass_size);
  }
  EmissionDraws draws(random, sobol ? &*sobol : nullptr, point);
  PathLight light = PathLight::directional;
  if (!emit(draws, ray, power, light)) return;
  follow(random, ray, power, light, nullptr, stats, on_receiver, on_segment, on_blocked);
}

// The path from an emitted ray on. With `differential`, its ray differentials are carried along: moved
// to every hit and turned by every reflection and refraction (core/ray_differential.h).
// With `on_blocked`, the path blocked on its way to its first specular object goes on as a blocked path
// (`blocked`), and a photon that reached a receiver is followed through it (Blocked, core/photon_tracer.h).
template <class OnReceiver, class OnSegment>
void CausticPhotonTracer::follow(Random& random, Ray ray, Color power, PathLight light, RayDifferential* differential,
                                 PhotonStats& stats, OnReceiver&& on_receiver, OnSegment&& on_segment,
                                 const BlockedVisit* on_blocked) const {
  const Scene& scene = *tracer_.frame().scene;
  float initial = max_component(power);
  int specular_bounces = 0;
  bool blocked = false;
  PathClassifier path;
  const Material* medium = nullptr;  // the glass the photon travels in, if any
  for (int depth = 0; depth <= settings_.max_bounces; ++depth) {
    SurfaceHit hit;
    ++stats.rays;
    bool found = tracer_.intersect(ray, hit);
    if (specular_bounces > 0) {
      // Inside glass (a pool floor lies under water) the power is taken at the segment's middle; an
      // endless segment in a medium keeps the power it started with.
      Color carried = medium && found ? power * glm::exp(-medium->absorption * (0.5f * hit.t)) : power;
      on_segment(PathSegment{ray.origin, ray.direction, found ? hit.t : std::numeric_limits<float>::infinity(), carried});
    }
    if (!found) return;
    if (differential) transfer_differential(*differential, ray.direction, hit.t, hit.geometric_normal);
    // The segment just travelled was inside a glass medium (also when it ends on a surface inside
    // it, such as a pool floor under water): Beer-Lambert absorption over its length.
    if (medium) power *= glm::exp(-medium->absorption * hit.t);
    const Material& material = scene.objects[hit.object].material;
    bool from_outside = glm::dot(ray.direction, hit.geometric_normal) < 0.0f;
    if (material.receives_caustics()) {
      if (specular_bounces > 0) {
        Vec3 arrival_normal = from_outside ? hit.geometric_normal : -hit.geometric_normal;
        const PathClass arrived{path.interaction(), light, path_receiver_of(material), blocked};
        if (blocked) {
          // Where the blocked light would have arrived; inside a closed occluder it goes on.
          if (records_blocked_on(hit, ray.direction)) {
            (*on_blocked)(hit, arrival_normal, ray.direction, power, arrived.packed());
            return;
          }
          ray = tracer_.spawn(hit, ray.direction);
          continue;
        }
        on_receiver(hit, arrival_normal, ray.direction, power, arrived.packed());
        ++stats.deposited;
        if (on_blocked) follow_through_receivers(hit, ray.direction, power, arrived, stats, *on_blocked);
      } else if (on_blocked && material.kind != MaterialKind::diffuse_mirror) {
        // Nothing specular met yet: this surface blocks the light on its way to a specular object. A method
        // that does not model occlusion lets it through, so the path goes on, blocked, while it still heads
        // for a target.
        if (!heads_for_a_target(hit.position, ray.direction)) return;
        blocked = true;
        ray = tracer_.spawn(hit, ray.direction);
        continue;
      }
      if (material.kind != MaterialKind::diffuse_mirror) return;
    }
    const bool flipped = glm::dot(ray.direction, hit.shading_normal) >= 0.0f;
    Vec3 normal = flipped ? -hit.shading_normal : hit.shading_normal;
    float cos_incident = -glm::dot(ray.direction, normal);
    Vec3 dn_du(0.0f), dn_dv(0.0f);
    if (differential) {
      dn_du = tracer_.shading_normal_change(hit, differential->dp_du);
      dn_dv = tracer_.shading_normal_change(hit, differential->dp_dv);
      if (flipped) dn_du = -dn_du, dn_dv = -dn_dv;
    }
    Vec3 next;
    bool refracted = false;
    float eta = 1.0f;
    if (material.kind == MaterialKind::glass) {
      eta = from_outside ? material.ior : 1.0f / material.ior;
      float reflectance = fresnel_dielectric(cos_incident, eta);
      // Choosing reflection with probability F and refraction with 1 - F leaves the power unchanged.
      if (random.uniform() < reflectance || !refract(ray.direction, normal, eta, next)) {
        next = reflect(ray.direction, normal);
        path.reflection(hit.object, !from_outside);
      } else {
        medium = from_outside ? &material : nullptr;
        refracted = true;
        path.refraction(hit.object, from_outside);
      }
    } else {
      power *= material.mirror_reflectance(cos_incident);
      next = reflect(ray.direction, normal);
      path.reflection(hit.object, medium != nullptr);
    }
    if (differential) {
      if (refracted) {
        refract_differential(*differential, ray.direction, normal, dn_du, dn_dv, eta);
      } else {
        reflect_differential(*differential, ray.direction, normal, dn_du, dn_dv);
      }
    }
    ++specular_bounces;
    if (specular_bounces >= settings_.roulette_after) {
      float survival = std::min(1.0f, max_component(power) / initial);
      if (random.uniform() >= survival) return;
      power /= survival;
    }
    if (max_component(power) <= 0.0f) return;
    ray = tracer_.spawn(hit, next);
  }
  if (blocked) return;  // light that never arrived is not cut light
  ++stats.cut;
  stats.cut_flux += luminance(power);
}

void CausticPhotonTracer::follow_through_receivers(const SurfaceHit& hit, const Vec3& direction, const Color& power,
                                                   PathClass path, PhotonStats& stats,
                                                   const BlockedVisit& on_blocked) const {
  const Scene& scene = *tracer_.frame().scene;
  // Only where a receiver's box lies ahead (the one just reached counts unless it is a quad or a disk, which
  // a straight line leaves for good): a floor under glass, or beside a wall standing on it, costs no ray.
  bool ahead = false;
  for (const WorldBox& receiver : receivers_) {
    const ShapeKind kind = scene.objects[receiver.object].shape.kind;
    if (receiver.object == hit.object && (kind == ShapeKind::quad || kind == ShapeKind::disk)) continue;
    if ((ahead = meets_box_ahead(receiver, hit.position, direction))) break;
  }
  if (!ahead) return;
  path.blocked = true;
  Ray ray = tracer_.spawn(hit, direction);
  for (int surface = 0; surface < settings_.max_bounces; ++surface) {
    SurfaceHit next;
    ++stats.rays;
    if (!tracer_.intersect(ray, next)) return;
    const Material& material = scene.objects[next.object].material;
    // A specular object beyond: what it would do with the light is another path, which no method without
    // occlusion computes either.
    if (!material.receives_caustics()) return;
    if (records_blocked_on(next, direction)) {
      path.receiver = path_receiver_of(material);
      const bool from_outside = glm::dot(direction, next.geometric_normal) < 0.0f;
      on_blocked(next, from_outside ? next.geometric_normal : -next.geometric_normal, direction, power, path.packed());
    }
    ray = tracer_.spawn(next, direction);
  }
}

bool CausticPhotonTracer::meets_sphere_ahead(const BoundingSphere& sphere, const Vec3& origin, const Vec3& direction) {
  // The line meets the sphere, and its far intersection lies ahead (t > 0).
  const float length2 = glm::dot(direction, direction);
  const Vec3 to_center = sphere.center - origin;
  const float along = glm::dot(to_center, direction) / length2;
  const float miss2 = glm::dot(to_center, to_center) - along * along * length2;
  const float r2 = sphere.radius * sphere.radius;
  return miss2 <= r2 && along + std::sqrt((r2 - miss2) / length2) > 0.0f;
}

bool CausticPhotonTracer::meets_box_ahead(const WorldBox& box, const Vec3& origin, const Vec3& direction) {
  // Slabs: the line's interval inside the box, which must reach beyond the spawn offset ahead; an
  // axis-parallel line is inside the slab of that axis or misses the box.
  float near = -std::numeric_limits<float>::infinity(), far = std::numeric_limits<float>::infinity();
  for (int axis = 0; axis < 3; ++axis) {
    if (direction[axis] == 0.0f) {
      if (origin[axis] < box.lower[axis] || origin[axis] > box.upper[axis]) return false;
      continue;
    }
    float t0 = (box.lower[axis] - origin[axis]) / direction[axis], t1 = (box.upper[axis] - origin[axis]) / direction[axis];
    if (t0 > t1) std::swap(t0, t1);
    near = std::max(near, t0);
    far = std::min(far, t1);
  }
  return near <= far && far > 1e-4f * (1.0f + glm::length(origin)) / glm::length(direction);
}

// The targets' world boxes rather than their bounding spheres, which reach through the floor an object
// stands on: a photon aimed at a ring that misses it and meets the floor inside the ring's sphere would be
// followed on below the floor, a ray for nothing.
bool CausticPhotonTracer::heads_for_a_target(const Vec3& origin, const Vec3& direction) const {
  for (const WorldBox& target : target_boxes_)
    if (meets_box_ahead(target, origin, direction)) return true;
  return false;
}

bool CausticPhotonTracer::is_closed(const ShapeDesc& shape) {
  // Solids, whose inside faces no receiver is seen by: a blocked path passes through them.
  return shape.kind == ShapeKind::sphere || shape.kind == ShapeKind::box || shape.kind == ShapeKind::prism ||
         shape.kind == ShapeKind::torus || (shape.kind == ShapeKind::ring && shape.thickness > 0.0);
}

bool CausticPhotonTracer::records_blocked_on(const SurfaceHit& hit, const Vec3& direction) const {
  return !is_closed(tracer_.frame().scene->objects[hit.object].shape) || glm::dot(direction, hit.geometric_normal) < 0.0f;
}

void CausticPhotonTracer::trace_emitted(uint64_t index, const Ray& ray, const Color& power, RayDifferential differential,
                                        PhotonStats& stats, const DifferentialVisit& visit) const {
  Random random(settings_.seed, index);
  ++stats.emitted;
  // The caller's emission map knows its light; the path class is not reported here.
  follow(
      random, ray, power, PathLight::directional, &differential, stats,
      [&](const SurfaceHit& hit, const Vec3& arrival_normal, const Vec3& direction, const Color& carried, uint8_t) {
        visit(hit, arrival_normal, direction, carried, differential);
      },
      [](const PathSegment&) {});
}

void CausticPhotonTracer::trace_one(uint64_t index, std::vector<Photon>& photons, PhotonStats& stats) const {
  trace_path(index, photons, stats, nullptr, nullptr);
}

void CausticPhotonTracer::trace_path(uint64_t index, std::vector<Photon>& photons, PhotonStats& stats,
                                     std::vector<uint8_t>* classes, Blocked* blocked) const {
  BlockedVisit record_blocked;
  if (blocked) {
    record_blocked = [blocked](const SurfaceHit& hit, const Vec3& arrival_normal, const Vec3& direction,
                               const Color& power, uint8_t path) {
      blocked->photons.push_back(Photon{hit.position, arrival_normal, direction, power});
      blocked->classes.push_back(path);
    };
  }
  walk(
      index, stats,
      [&](const SurfaceHit& hit, const Vec3& arrival_normal, const Vec3& direction, const Color& power, uint8_t path) {
        photons.push_back(Photon{hit.position, arrival_normal, direction, power});
        if (classes) classes->push_back(path);
      },
      [](const PathSegment&) {}, blocked ? &record_blocked : nullptr);
}

void CausticPhotonTracer::trace_segments(uint64_t index, PhotonStats& stats,
                                         const std::function<void(const PathSegment&)>& visit) const {
  walk(index, stats, [](const SurfaceHit&, const Vec3&, const Vec3&, const Color&, uint8_t) {}, visit);
}

void CausticPhotonTracer::trace(uint64_t first, uint64_t count, std::vector<Photon>& photons, PhotonStats& stats) const {
  trace_blocks(first, count, photons, stats, nullptr, nullptr);
}

void CausticPhotonTracer::trace(uint64_t first, uint64_t count, std::vector<Photon>& photons, PhotonStats& stats,
                                std::vector<uint8_t>& classes, Blocked* blocked) const {
  trace_blocks(first, count, photons, stats, &classes, blocked);
}

void CausticPhotonTracer::trace_blocks(uint64_t first, uint64_t count, std::vector<Photon>& photons,
                                       PhotonStats& stats, std::vector<uint8_t>* classes, Blocked* blocked) const {
  if (targets_.empty() || total_weight_ <= 0.0) {
    stats.emitted += count;
    return;
  }
  const size_t block_size = 8192;
  size_t blocks = (count + block_size - 1) / block_size;
  std::vector<std::vector<Photon>> block_photons(blocks);
  std::vector<std::vector<uint8_t>> block_classes(classes ? blocks : 0);
  std::vector<Blocked> block_blocked(blocked ? blocks : 0);
  std::vector<PhotonStats> block_stats(blocks);
  parallel_blocks(count, block_size, [&](size_t begin, size_t end, size_t block) {
    std::vector<Photon>& local = block_photons[block];
    local.reserve((end - begin) / 2);
    for (size_t i = begin; i < end; ++i)
      trace_path(first + i, local, block_stats[block], classes ? &block_classes[block] : nullptr,
                 blocked ? &block_blocked[block] : nullptr);
  });
  size_t total = photons.size();
  for (const auto& block : block_photons) total += block.size();
  photons.reserve(total);
  if (classes) classes->reserve(classes->size() + total - photons.size());
  for (size_t block = 0; block < blocks; ++block) {
    photons.insert(photons.end(), block_photons[block].begin(), block_photons[block].end());
    if (classes) classes->insert(classes->end(), block_classes[block].begin(), block_classes[block].end());
    if (blocked) {
      const Blocked& local = block_blocked[block];
      blocked->photons.insert(blocked->photons.end(), local.photons.begin(), local.photons.end());
      blocked->classes.insert(blocked->classes.end(), local.classes.begin(), local.classes.end());
    }
    stats.add(block_stats[block]);
  }
}

}  // namespace causticbench
