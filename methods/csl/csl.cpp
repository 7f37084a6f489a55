#include "methods/csl/csl.h"

#include <cmath>

#include <fmt/format.h>

#include "core/errors.h"
#include "core/parallel.h"
#include "core/progress.h"

namespace causticbench {

using namespace csl;

const MethodInfo& CslMethod::static_info() {
  static const MethodInfo info = [] {
    MethodInfo m;
    m.name = "csl";
    m.paper = "X. Liu, Z. Dong, H. Bao, Q. Peng, \"Caustic spot light for rendering caustics\", The Visual Computer 24, 2008";
    m.summary = "Traces a grid of parallel light rays through each specular object once, clusters the rays that leave it "
                "into bundles and fits each bundle with a caustic spot light (a light plane whose rays focus along its "
                "axis, f(r) = alpha / (1 + beta r), with an intensity image); per frame every receiver point sums the "
                "spot lights' rays that reach it, found in closed form.";
    m.params = {
        ParamSpec::integer("rays_per_side", 1280, 2, 8192,
                           "parallel rays per side of the square over the object's bounding sphere (the paper: 1280)",
                           ParamPhase::build),
        ParamSpec::real("min_energy", 0.01, 0.0, 1.0,
                        "a reflected or refracted branch is dropped below this fraction of its ray's starting energy",
                        ParamPhase::build),
        ParamSpec::integer("raster_resolution", 64, 4, 512,
                           "cells along each axis of the grid the rays' lines are rasterised into (Section 3.1.1, step 1)",
                           ParamPhase::build),
        ParamSpec::real("raster_extent", 4.0, 1.0, 100.0,
                        "half the side of that grid's cube, in bounding radii of the object (the extended bounding volume)",
                        ParamPhase::build),
        ParamSpec::real("distance_threshold", 0.1, 1e-6, 100.0,
                        "largest distance between a ray's line and a bundle's axis, in bounding radii", ParamPhase::build),
        ParamSpec::real("angle_threshold", 90.0, 0.0, 90.0,
                        "largest angle between a ray and a bundle's axis, degrees (the paper's bundle definition: 90)",
                        ParamPhase::build),
        ParamSpec::real("energy_coverage", 0.95, 0.0, 1.0,
                        "spot lights are made until this fraction of the rays' energy is covered (the paper: 0.95)",
                        ParamPhase::build),
        ParamSpec::integer("max_csls", 64, 1, 4096, "spot lights per object and light direction at most", ParamPhase::build),
        ParamSpec::integer("fit_rays", 1024, 1, 1e7,
                           "rays of a bundle that Eq. 5 sums over in the fit (evenly strided; all of them go into the image)",
                           ParamPhase::build),
        ParamSpec::real("fit_tolerance", 0.3, 0.0, 2.0,
                        "a bundle ray whose direction differs from its spot light ray's by more (|d - e|, about radians) "
                        "is dismissed from the bundle",
                        ParamPhase::build),
        ParamSpec::real("splat_scale", 3.0, 0.1, 100.0,
                        "delta, the rays' splat radius, in ray spacings: their spacing on the object (the paper: 3 of them) or, where wider, "
                        "on the light plane", ParamPhase::build),
        ParamSpec::choice("image_size", "auto", {"auto", "128", "256", "512"},
                          "texels per side of the intensity images; auto: 128, 256 or 512 per spot light by the size of "
                          "its image on the light plane, as the paper chose",
                          ParamPhase::build),
        ParamSpec::choice("precision", "uint16", {"uint16", "float32"},
                          "intensity image texels: 16-bit integers with a scale per image (the paper) or floats",
                          ParamPhase::build),
        ParamSpec::choice("intensity_correction", "on", {"on", "off"},
                          "divide each ray's intensity by the area ratio of Eq. 4 (Fig. 6 compares on and off)",
                          ParamPhase::render),
        ParamSpec::choice("on_axis", "integrate", {"integrate", "epsilon"},
                          "points whose footprint reaches the axis: the flux through that disk over its area (integrate), "
                          "or moved out to axis_epsilon from it (the paper's epsilon)",
                          ParamPhase::render),
        ParamSpec::real("axis_epsilon", 1e-4, 1e-9, 1.0, "on_axis: epsilon: the distance, in bounding radii",
                        ParamPhase::render)
            .only_when("on_axis", {"epsilon"}),
    };
    Capabilities& c = m.capabilities;
    c.refraction = true;
    c.directional_light = true;
    c.moving_objects = true;
    c.non_lambertian_receivers = true;
    c.notes = {
        {"reflection", "the reflection of a convex mirror (a hemisphere of directions) is cut into cones of spot lights "
                       "whose seams and coarse images show: measured on the capability ellipsoid at 512 rays a side, "
                       "energy 0.79 and relMSE 4.3; the paper's objects are glass"},
        {"multiple_bounces", "any number within one object (the ray tree splits at every glass surface); none between "
                             "objects: each object's spot lights are made from that object alone"},
        {"point_light", "taken as a directional light from the object's centre, with the irradiance there"},
        {"environment_light", "refused (Liu 2008, Table 1)"},
        {"moving_light", "not yet: the interpolated sets of Section 4 are not built; a light whose direction in an "
                         "object's frame changes over the rendered frames is refused"},
        {"moving_objects", "the spot lights move with their object; an object that turns under a fixed light changes the "
                           "light's direction in its frame, which is refused until Section 4's sets are built"},
        {"occlusion", "the caustic light reaches receivers behind other objects (no shadow rays yet)"},
        {"non_lambertian_receivers", "E_c is irradiance, whatever the receiver's BRDF; the spot lights know each ray's "
                                     "direction, so view-dependent shading could use it"},
    };
    m.quick_knobs = {"rays_per_side=48", "image_size=128"};
    m.counters = {counter_quantity("spot_lights", "lights", "caustic spot lights over all objects and light directions"),
                  counter_quantity("caustic_rays", "rays", "caustic object rays that left the objects (all directions)"),
                  counter_quantity("csl_evaluations", "evaluations", "spot light evaluations in the last frame"),
                  counter_quantity("image_bytes", "bytes", "intensity images, all spot lights", QuantityKind::size)};
    return m;
  }();
  return info;
}

GenerateSettings csl::generate_settings(const ParamSet& build, const BoundingSphere& bounds, double ray_spacing) {
  GenerateSettings settings;
  const double radius = bounds.radius;
  settings.bundle.raster_resolution = static_cast<int>(build.integer("raster_resolution"));
  settings.bundle.raster_half_size = build.real("raster_extent") * radius;
  settings.bundle.distance_threshold = build.real("distance_threshold") * radius;
  settings.bundle.cos_angle_threshold = std::cos(build.real("angle_threshold") * kPiDouble / 180.0);
  settings.fit.reach = 4.0 * 2.0 * radius;  // four times the bounding box's size
  settings.fit.max_rays = static_cast<int>(build.integer("fit_rays"));
  settings.fit.plane_range = 2.0 * radius;  // one object diameter behind the rays' origins
  settings.splat.spacing = ray_spacing;
  settings.splat.splat_scale = build.real("splat_scale");
  settings.splat.image_size = build.text("image_size") == "auto" ? 0 : std::stoi(build.text("image_size"));
  settings.splat.precision = build.text("precision") == "uint16" ? IntensityImage::Precision::uint16
                                                                 : IntensityImage::Precision::float32;
  settings.energy_coverage = build.real("energy_coverage");
  settings.max_lights = static_cast<int>(build.integer("max_csls"));
  settings.fit_tolerance = build.real("fit_tolerance");
  return settings;
}

EvaluationSettings csl::evaluation_settings(const ParamSet& render, const BoundingSphere& bounds) {
  EvaluationSettings settings;
  settings.intensity_correction = render.text("intensity_correction") == "on";
  settings.on_axis = render.text("on_axis") == "integrate" ? OnAxis::integrate : OnAxis::epsilon;
  if (settings.on_axis == OnAxis::epsilon) settings.axis_epsilon = render.real("axis_epsilon") * bounds.radius;
  return settings;
}

void CslMethod::check_scene(const Scene& scene) const {
  if (!scene.has_specular_object()) {
    throw InputError(fmt::format("{}: csl makes spot lights from the light leaving specular objects, and the scene has none",
                                 scene.source));
  }
  for (const Light& light : scene.lights) {
    if (light.kind == LightKind::environment_image || light.kind == LightKind::gaussian_spot) {
      throw InputError(fmt::format("{}: light '{}' is an environment light; csl renders directional and point lights only "
                                   "(Liu 2008, Table 1)",
                                   scene.source, light.name));
    }
  }
}

void CslMethod::prepare(const PrepareContext& context, const ParamSet& build) {
  scene_ = &context.scene;
  objects_.clear();
  frame_.clear();
  rays_traced_ = 0.0;
  // Every object's light directions first, so that a scene this build cannot serve is refused before
  // any ray is traced.
  std::vector<std::vector<Vec3>> directions;
  std::vector<Scene> alone_scenes;
  for (int object : context.rest.specular_objects()) {
    ObjectSets sets;
    sets.object = object;
    sets.name = context.scene.objects[object].name;
    alone_scenes.push_back(build_space_scene(context.scene, object));
    sets.bounds = SceneFrame(alone_scenes.back(), 0.0).bounds[0];
    const auto per_light = object_light_directions(context.scene, object, sets.bounds.center, context.frames);
    const std::optional<std::vector<Vec3>> fixed = fixed_light_directions(per_light);
    bool any = false;
    for (const auto& light : per_light) any = any || !light.empty();
    if (any && !fixed) {
      throw InputError(fmt::format(
          "{}: the light's direction in the frame of object '{}' changes over the {} rendered frame(s); csl builds one "
          "static set of spot lights per direction, and the interpolated sets of Section 4 (dynamic light) are not built "
          "yet: render frames in which the light keeps its direction to the object",
          context.scene.source, sets.name, context.frames.size()));
    }
    sets.set_kind = "static";
    sets.reason = fmt::format("the light's direction in the object's frame does not change over the {} rendered frame(s): "
                              "{} static set(s), one per direction",
                              context.frames.size(), fixed ? fixed->size() : 0);
    directions.push_back(fixed ? *fixed : std::vector<Vec3>{});
    objects_.push_back(std::move(sets));
  }
  size_t total = 0;
  for (const auto& list : directions) total += list.size();
  Progress progress("csl light directions", static_cast<double>(total));
  size_t done = 0;
  const int rays_per_side = static_cast<int>(build.integer("rays_per_side"));
  SpecularTreeSettings tree;
  tree.min_energy = static_cast<float>(build.real("min_energy"));
  for (size_t i = 0; i < objects_.size(); ++i) {
    ObjectSets& sets = objects_[i];
    const SceneFrame frame(alone_scenes[i], 0.0);
    const Tracer tracer(frame);
    for (const Vec3& direction : directions[i]) {
      const ObjectRays rays = trace_object_rays(tracer, sets.bounds, direction, rays_per_side, tree);
      rays_traced_ += static_cast<double>(rays.rays.size());
      GenerateSettings settings = generate_settings(build, sets.bounds, rays.spacing);
      // One channel unless the object colours the light.
      settings.splat.channels = 1;
      for (const CausticRay& ray : rays.rays) {
        const float largest = max_component(ray.energy);
        if (std::fabs(ray.energy.r - ray.energy.g) > 1e-5f * largest || std::fabs(ray.energy.r - ray.energy.b) > 1e-5f * largest) {
          settings.splat.channels = 3;
          break;
        }
      }
      SpotLightSet set = generate_spot_lights(rays, sets.bounds, settings);
      set.direction = direction;
      sets.sets.push_back(std::move(set));
      progress.update(static_cast<double>(++done), sets.name);
    }
  }
  progress.finish();
}

void CslMethod::update(const FrameContext& frame, const ParamSet&) {
  frame_.assign(objects_.size(), ObjectFrame{});
  for (size_t i = 0; i < objects_.size(); ++i) {
    const ObjectSets& sets = objects_[i];
    ObjectFrame& view = frame_[i];
    view.map = build_space_map(scene_->objects[sets.object], frame.frame.frame);
    view.length_scale = std::cbrt(std::fabs(glm::determinant(view.map.linear)));
    for (const LightFrame& light : frame.frame.lights) {
      const ObjectLight seen = object_light(view.map, light, sets.bounds.center);
      if (!seen.valid || sets.sets.empty()) continue;
      const SpotLightSet* best = &sets.sets.front();
      for (const SpotLightSet& set : sets.sets) {
        if (glm::dot(set.direction, seen.direction) > glm::dot(best->direction, seen.direction)) best = &set;
      }
      if (glm::length(best->direction - seen.direction) > 1e-4f) {
        throw std::logic_error(fmt::format("csl: object '{}' sees a light direction no set was made for", sets.name));
      }
      view.lights.push_back(LightView{best, seen.irradiance});
    }
  }
}

Image CslMethod::render(const GBuffer& gbuffer, const ParamSet& render) {
  Image result(gbuffer.width, gbuffer.height, 3);
  std::vector<double> evaluations(gbuffer.pixel_count() / 1024 + 1, 0.0);
  std::vector<EvaluationSettings> settings_of;  // per object (axis_epsilon is in its bounding radii)
  for (const ObjectSets& sets : objects_) settings_of.push_back(evaluation_settings(render, sets.bounds));
  parallel_blocks(gbuffer.pixel_count(), 1024, [&](size_t begin, size_t end, size_t) {
    double count = 0.0;
    for (size_t i = 0; i < objects_.size(); ++i) {
      const ObjectFrame& view = frame_[i];
      if (view.lights.empty()) continue;
      const EvaluationSettings& settings = settings_of[i];
      for (size_t pixel = begin; pixel < end; ++pixel) {
        if (!gbuffer.receiver[pixel]) continue;
        const Vec3 point = view.map.point(gbuffer.position[pixel]);
        const Vec3 normal = glm::normalize(view.map.normals * gbuffer.normal[pixel]);
        // The disk of the pixel's footprint: the same area as its square.
        const float footprint = gbuffer.footprint[pixel] * view.length_scale / std::sqrt(kPi);
        Color total(0.0f);
        for (const LightView& light : view.lights) {
          for (const SpotLight& spot : light.set->lights) {
            float value[3] = {0.0f, 0.0f, 0.0f};
            spot.evaluate(point, normal, footprint, settings, value);
            count += 1.0;
            const Color added = spot.image.channels() == 1 ? Color(value[0]) : Color(value[0], value[1], value[2]);
            total += added * light.irradiance;
          }
        }
        const Color before(result.at(pixel, 0), result.at(pixel, 1), result.at(pixel, 2));
        result.set_rgb(pixel, before + total);
      }
    }
    evaluations[begin / 1024] = count;
  });
  evaluations_ = 0.0;
  for (double count : evaluations) evaluations_ += count;
  return result;
}

size_t CslMethod::memory_bytes() const {
  size_t bytes = 0;
  for (const ObjectSets& sets : objects_) {
    for (const SpotLightSet& set : sets.sets) bytes += set.memory_bytes();
  }
  return bytes;
}

Counters CslMethod::counters() const {
  double lights = 0.0, bytes = 0.0;
  for (const ObjectSets& sets : objects_) {
    for (const SpotLightSet& set : sets.sets) {
      lights += static_cast<double>(set.lights.size());
      bytes += static_cast<double>(set.memory_bytes());
    }
  }
  return {{"spot_lights", lights}, {"caustic_rays", rays_traced_}, {"csl_evaluations", evaluations_}, {"image_bytes", bytes}};
}

nlohmann::json CslMethod::record() const {
  nlohmann::json objects = nlohmann::json::array();
  for (const ObjectSets& sets : objects_) {
    nlohmann::json list = nlohmann::json::array();
    for (const SpotLightSet& set : sets.sets) list.push_back(set.to_json());
    objects.push_back({{"object", sets.name}, {"light_sample_set", sets.set_kind}, {"why", sets.reason}, {"sets", list}});
  }
  return {{"objects", objects}};
}

}  // namespace causticbench
