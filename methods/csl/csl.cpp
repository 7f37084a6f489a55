#include "methods/csl/csl.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "core/errors.h"
#include "core/progress.h"

namespace causticbench {

using namespace csl;

void CslMethod::check_scene(const Scene& scene) const {
  require_specular_object(scene, "csl makes spot lights from the light leaving specular objects");
  for (const Light& light : scene.lights) {
    if (light.kind == LightKind::environment_image || light.kind == LightKind::gaussian_spot) {
      throw InputError(fmt::format("{}: light '{}' is an environment light; csl renders directional and point lights only "
                                   "(Liu 2008, Table 1)",
                                   scene.source, light.name));
    }
  }
}

SpotLightSet csl::make_spot_light_set(const Tracer& tracer, const BoundingSphere& bounds, const Vec3& direction, const ParamSet& build) {
  SpecularTreeSettings tree;
  tree.min_energy = static_cast<float>(build.real("min_energy"));
  const ObjectRays rays = trace_object_rays(tracer, bounds, direction, static_cast<int>(build.integer("rays_per_side")), tree);
  GenerateSettings settings = generate_settings(build, bounds, rays.spacing);
  // One channel unless the object colours the light.
  settings.splat.channels = 1;
  for (const CausticRay& ray : rays.rays) {
    const float largest = max_component(ray.energy);
    if (std::fabs(ray.energy.r - ray.energy.g) > 1e-5f * largest || std::fabs(ray.energy.r - ray.energy.b) > 1e-5f * largest) {
      settings.splat.channels = 3;
      break;
    }
  }
  SpotLightSet set = generate_spot_lights(rays, bounds, settings);
  set.direction = direction;
  return set;
}

CslMethod::Plan CslMethod::make_plan(const PrepareContext& context, const ParamSet& build,
                                     std::unique_ptr<SphericalMesh>& mesh) {
  Plan plan;
  const bool all = build.text("light_samples") == "all";
  const int level = static_cast<int>(build.integer("light_subdivision"));
  for (int object : context.rest.specular_objects()) {
    ObjectSets sets;
    sets.object = object;
    sets.name = context.scene.objects[object].name;
    plan.alone.push_back(build_space_scene(context.scene, object));
    sets.bounds = SceneFrame(plan.alone.back(), 0.0).bounds[0];
    const auto per_light = object_light_directions(context.scene, object, sets.bounds.center, context.frames);
    const std::optional<std::vector<Vec3>> fixed = fixed_light_directions(per_light);
    std::vector<Vec3> seen;
    for (const auto& light : per_light) seen.insert(seen.end(), light.begin(), light.end());
    if (!all && (fixed || seen.empty())) {
      sets.set_kind = "static";
      sets.reason = fmt::format("the light's direction in the object's frame does not change over the {} rendered "
                                "frame(s): {} static set(s), one per direction",
                                context.frames.size(), fixed ? fixed->size() : 0);
      plan.static_directions.push_back(fixed ? *fixed : std::vector<Vec3>{});
      plan.dynamic.emplace_back();
      plan.facets.emplace_back();
    } else {
      if (!mesh) mesh = std::make_unique<SphericalMesh>(SphericalMesh::geodesic_vertices(level));
      DynamicPlan dynamic;
      dynamic.level = level;
      dynamic.all = all;
      dynamic.directions = seen;
      plan.facets.push_back(planned_facets(*mesh, dynamic));
      const size_t facets = plan.facets.back().size();
      sets.set_kind = "dynamic";
      sets.reason = all ? fmt::format("light_samples: all: every one of the {} facets of the icosahedron subdivided {} "
                                      "time(s)",
                                      facets, level)
                        : fmt::format("the light's direction in the object's frame changes over the {} rendered frame(s): "
                                      "the {} facet(s) of the icosahedron subdivided {} time(s) that those directions "
                                      "fall in, of {}",
                                      context.frames.size(), facets, level, mesh->triangles().size());
      plan.static_directions.emplace_back();
      plan.dynamic.push_back(dynamic);
    }
    plan.objects.push_back(std::move(sets));
  }
  return plan;
}

void CslMethod::prepare(const PrepareContext& context, const ParamSet& build) {
  scene_ = &context.scene;
  frame_.clear();
  mesh_.reset();
  forget_gpu_images();
  // The plan first (static directions or the facets of each dynamic set), then the work.
  Plan plan = make_plan(context, build, mesh_);
  objects_ = std::move(plan.objects);
  for (size_t i = 0; i < objects_.size(); ++i) {
    ObjectSets& sets = objects_[i];
    const SceneFrame frame(plan.alone[i], 0.0);
    const Tracer tracer(frame);
    auto make = [&](const Vec3& direction) { return make_spot_light_set(tracer, sets.bounds, direction, build); };
    if (plan.dynamic[i]) {
      sets.dynamic = build_dynamic_sets(tracer, sets.bounds, *mesh_, *plan.dynamic[i], make, tracking_settings(build, sets.bounds));
      check_some_spot_light(sets.name, sets.dynamic->sets, build);
      continue;
    }
    Progress progress("csl light directions", static_cast<double>(plan.static_directions[i].size()));
    for (const Vec3& direction : plan.static_directions[i]) {
      sets.sets.push_back(make(direction));
      progress.update(static_cast<double>(sets.sets.size()), sets.name);
    }
    progress.finish();
    check_some_spot_light(sets.name, sets.sets, build);
  }
  count_rays();
}

// An object whose rays carry caustic light but for which no spot light was made in any direction would
// render black, silently: the build knobs dismissed every bundle (energy_coverage 0 asks for none; a
// distance_threshold, angle_threshold or fit_tolerance of about 0 admits no ray, since no two rays are
// exactly coaxial in floating point). Found by the extremes study (study_extremes_knobs.yaml). An
// object with no caustic rays at all (fully absorbing, or min_energy dropping every branch) renders
// black rightly and passes.
void CslMethod::check_some_spot_light(const std::string& object, const std::vector<csl::SpotLightSet>& sets,
                                      const ParamSet& build) {
  double ray_energy = 0.0;
  for (const SpotLightSet& set : sets) {
    if (!set.lights.empty()) return;
    ray_energy += set.ray_energy;
  }
  if (!(ray_energy > 0.0)) return;
  // The defaults named in the advice are the knobs' declared ones (no knob set, resolved), so they stay
  // true when a default changes (distance_threshold did, from 0.1 to 0.3).
  const ParamSet defaults = ParamDict().resolve(static_info().params, "csl");
  throw InputError(fmt::format(
      "csl made no caustic spot light for object '{}' in any of its {} light direction(s), though its rays carry "
      "caustic light: the build knobs dismissed every bundle (energy_coverage {}, distance_threshold {}, "
      "angle_threshold {}, fit_tolerance {}); its image would be black. Raise energy_coverage above 0 or the "
      "thresholds (defaults {}, {}, {}, {})",
      object, sets.size(), build.real("energy_coverage"), build.real("distance_threshold"),
      build.real("angle_threshold"), build.real("fit_tolerance"), defaults.real("energy_coverage"),
      defaults.real("distance_threshold"), defaults.real("angle_threshold"), defaults.real("fit_tolerance")));
}

void CslMethod::count_rays() {
  rays_traced_ = 0.0;
  for (const ObjectSets& sets : objects_) {
    for (const SpotLightSet& set : sets.sets) rays_traced_ += set.rays;
    if (!sets.dynamic) continue;
    for (const SpotLightSet& set : sets.dynamic->sets) rays_traced_ += set.rays;
  }
}

void CslMethod::update_dynamic(const ObjectSets& sets, const Vec3& direction, const ParamSet& frame_knobs,
                               LightView& view) const {
  const DynamicSets& dynamic = *sets.dynamic;
  const SphericalMesh::Location location = mesh_->locate(direction);
  const DynamicSets::Facet* facet = dynamic.facet(location.triangle);
  if (facet == nullptr) {
    throw std::logic_error(fmt::format("csl: object '{}' sees a light direction in facet {}, which was not built",
                                       sets.name, location.triangle));
  }
  // A direction on a precomputed one (its weight exactly 1), or the nearest direction when asked: that
  // direction's own set, exactly (Section 4.3, rule 3).
  int largest = 0;
  for (int c = 1; c < 3; ++c) largest = location.weights[c] > location.weights[largest] ? c : largest;
  if (location.weights[largest] == 1.0f || frame_knobs.text("interpolation") == "nearest") {
    view.set = &dynamic.sets[facet->sets[largest]];
    view.ray_energy = view.set->ray_energy;
    view.covered_energy = view.set->covered_energy;
    view.misdirected_energy = view.set->misdirected_energy;
    return;
  }
  for (int c = 0; c < 3; ++c) {
    const SpotLightSet& corner = dynamic.sets[facet->sets[c]];
    view.ray_energy += location.weights[c] * corner.ray_energy;
    view.covered_energy += location.weights[c] * corner.covered_energy;
    view.misdirected_energy += location.weights[c] * corner.misdirected_energy;
  }
  const FocusInterpolation focus =
      frame_knobs.text("focus_interpolation") == "distance" ? FocusInterpolation::distance : FocusInterpolation::curvature;
  for (const Triple& triple : facet->triples) {
    std::array<TripleCorner, 3> corners;
    for (int c = 0; c < 3; ++c) {
      corners[c] = TripleCorner{dynamic.light(facet->sets[c], triple.light[c]), location.weights[c], triple.adds[c] != 0};
    }
    if (std::optional<InterpolatedSpotLight> light = interpolate_triple(corners, focus)) {
      view.interpolated.push_back(std::move(*light));
    }
  }
}

void CslMethod::update(const FrameContext& frame, const ParamSet& frame_knobs) {
  frame_.assign(objects_.size(), ObjectFrame{});
  tracer_ = &frame.tracer;
  forget_gpu_lights();
  interpolated_ = 0.0;
  for (size_t i = 0; i < objects_.size(); ++i) {
    const ObjectSets& sets = objects_[i];
    ObjectFrame& view = frame_[i];
    view.map = build_space_map(scene_->objects[sets.object], frame.frame.frame);
    view.length_scale = std::cbrt(std::fabs(glm::determinant(view.map.linear)));
    view.to_world = glm::inverse(view.map.linear);
    for (const LightFrame& light : frame.frame.lights) {
      const ObjectLight seen = object_light(view.map, light, sets.bounds.center);
      if (!seen.valid) continue;
      LightView light_view;
      light_view.irradiance = seen.irradiance;
      if (sets.dynamic) {
        update_dynamic(sets, seen.direction, frame_knobs, light_view);
        interpolated_ += static_cast<double>(light_view.interpolated.size());
      } else {
        if (sets.sets.empty()) continue;
        const SpotLightSet* best = &sets.sets.front();
        for (const SpotLightSet& set : sets.sets) {
          if (glm::dot(set.direction, seen.direction) > glm::dot(best->direction, seen.direction)) best = &set;
        }
        if (glm::length(best->direction - seen.direction) > 1e-4f) {
          throw std::logic_error(fmt::format("csl: object '{}' sees a light direction no set was made for", sets.name));
        }
        light_view.set = best;
        light_view.ray_energy = best->ray_energy;
        light_view.covered_energy = best->covered_energy;
        light_view.misdirected_energy = best->misdirected_energy;
      }
      view.lights.push_back(std::move(light_view));
    }
  }
}

// The energy of the object rays (the light leaving each object after its specular interactions) that
// the frame's spot lights do not carry where it goes: what bundle extraction left once energy_coverage was
// reached or its cells ran out, and the rays the bundles and fits dismissed (distance_threshold,
// fit_tolerance); and the rays a spot light carries more than kMisdirectedChord off their own direction,
// whose light its point focus moves (a torus's ring focus: issue 52 found csl's energy at 0.24 there while
// the uncovered rays were 4.4 %). Weighted by each light's irradiance; known from the build, so it costs the
// frame nothing.
std::optional<LostFlux> CslMethod::lost_flux(const FrameContext&, const GBuffer&, const ParamSet&) {
  double total = 0.0, covered = 0.0, misdirected = 0.0;
  for (const ObjectFrame& view : frame_) {
    for (const LightView& light : view.lights) {
      const double weight = luminance(light.irradiance);
      total += weight * light.ray_energy;
      covered += weight * light.covered_energy;
      misdirected += weight * light.misdirected_energy;
    }
  }
  LostFlux lost;
  const double uncovered = total > 0.0 ? std::clamp((total - covered) / total, 0.0, 1.0) : 0.0;
  const double moved = total > 0.0 ? std::clamp(misdirected / total, 0.0, 1.0) : 0.0;
  lost.fraction = std::min(1.0, uncovered + moved);
  lost.moved = std::min(moved, lost.fraction);
  lost.what = fmt::format("caustic ray energy no spot light carries (left past energy_coverage, or dismissed from "
                          "bundles and fits: {:.1f} %) or that a spot light carries more than {} rad off its own "
                          "direction (moved by its point focus: {:.1f} %)",
                          100.0 * uncovered, kMisdirectedChord, 100.0 * moved);
  if (moved > uncovered) {
    // Bundles of rays closer in direction and position give a ring or line focus to more spot lights, each
    // nearer its rays (the torus: angle_threshold 30 or distance_threshold 0.1 against 90 and 0.3).
    lost.knob = "angle_threshold";
    lost.advice = "lower angle_threshold (or distance_threshold), so that each bundle holds rays closer in direction "
                  "and its spot light sends them nearer where they go; the point focus of a spot light cannot hold a "
                  "ring or line focus";
  } else {
    lost.knob = "energy_coverage";
    lost.advice = "raise energy_coverage, or loosen distance_threshold and fit_tolerance, which dismiss rays";
  }
  return lost;
}

size_t CslMethod::memory_bytes() const {
  size_t bytes = mesh_ ? mesh_->memory_bytes() : 0;
  for (const ObjectSets& sets : objects_) {
    for (const SpotLightSet& set : sets.sets) bytes += set.memory_bytes();
    if (sets.dynamic) bytes += sets.dynamic->memory_bytes();
  }
  return bytes;
}

Counters CslMethod::counters() const {
  double lights = 0.0, bytes = 0.0, directions = 0.0, triples = 0.0, facets = 0.0;
  auto count = [&](const SpotLightSet& set) {
    lights += static_cast<double>(set.lights.size());
    bytes += static_cast<double>(set.memory_bytes());
    directions += 1.0;
  };
  for (const ObjectSets& sets : objects_) {
    for (const SpotLightSet& set : sets.sets) count(set);
    if (!sets.dynamic) continue;
    for (const SpotLightSet& set : sets.dynamic->sets) count(set);
    for (const DynamicSets::Facet& facet : sets.dynamic->facets) triples += static_cast<double>(facet.triples.size());
    facets += static_cast<double>(sets.dynamic->facets.size());
  }
  return {{"spot_lights", lights},
          {"caustic_rays", rays_traced_},
          {"csl_evaluations", evaluations_},
          {"image_bytes", bytes},
          {"light_directions", directions},
          {"spot_lights_per_direction", directions > 0.0 ? lights / directions : 0.0},
          {"triples_per_facet", facets > 0.0 ? triples / facets : 0.0},
          {"interpolated_spot_lights", interpolated_}};
}

nlohmann::json CslMethod::record() const {
  nlohmann::json objects = nlohmann::json::array();
  for (const ObjectSets& sets : objects_) {
    nlohmann::json list = nlohmann::json::array();
    for (const SpotLightSet& set : sets.sets) list.push_back(set.to_json());
    nlohmann::json object = {{"object", sets.name}, {"light_sample_set", sets.set_kind}, {"why", sets.reason}};
    if (sets.dynamic) {
      // Per direction the set's summary without its spot lights' list (162 of them would swamp the record).
      for (const SpotLightSet& set : sets.dynamic->sets) {
        nlohmann::json summary = set.to_json();
        summary.erase("lights");
        list.push_back(std::move(summary));
      }
      object["dynamic"] = sets.dynamic->summary();
    }
    object["sets"] = std::move(list);
    objects.push_back(std::move(object));
  }
  return {{"objects", objects}, {"gpu_device", gpu_device()}};
}

}  // namespace causticbench
