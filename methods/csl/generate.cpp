#include "methods/csl/generate.h"

#include <algorithm>
#include <chrono>

namespace causticbench::csl {

size_t SpotLightSet::memory_bytes() const {
  size_t bytes = 0;
  for (const SpotLight& light : lights) bytes += sizeof(SpotLight) + light.image.memory_bytes();
  return bytes;
}

nlohmann::json SpotLightSet::to_json() const {
  nlohmann::json list = nlohmann::json::array();
  for (size_t i = 0; i < lights.size(); ++i) {
    const SpotLight& light = lights[i];
    const SpotLightRecord& record = records[i];
    const double kappa = light.profile.kappa;
    list.push_back({{"alpha", kappa != 0.0 ? nlohmann::json(1.0 / kappa) : nlohmann::json("infinite")},
                    {"kappa", kappa},
                    {"beta", light.profile.beta},
                    {"ell", record.fit.ell},
                    {"image_size", light.image.size()},
                    {"image_half_size", light.image.half_size()},
                    {"bundle_rays", record.bundle_rays},
                    {"kept_rays", record.kept_rays},
                    {"energy", record.energy},
                    {"bundle_iterations", record.bundle_iterations},
                    {"bundle_converged", record.bundle_converged},
                    {"fit_rays", record.fit.rays_used},
                    {"fit_initial_objective", record.fit.initial_cost},
                    {"fit_objective", record.fit.final_cost},
                    {"fit_iterations", record.fit.iterations},
                    {"fit_converged", record.fit.converged},
                    {"fit_failed", record.fit.failed}});
  }
  return {{"direction", {direction.x, direction.y, direction.z}},
          {"spot_lights", lights.size()},
          {"rays", rays},
          {"ray_energy", ray_energy},
          {"covered_energy", covered_energy},
          {"coverage", ray_energy > 0.0 ? covered_energy / ray_energy : 0.0},
          {"misdirected_energy", misdirected_energy},
          {"seeds_tried", seeds_tried},
          {"trace_seconds", trace_seconds},
          {"cluster_seconds", cluster_seconds},
          {"image_bytes", memory_bytes()},
          {"lights", list}};
}

SpotLightSet generate_spot_lights(const ObjectRays& object_rays, const BoundingSphere& bounds,
                                  const GenerateSettings& settings) {
  const auto start = std::chrono::steady_clock::now();
  const std::vector<CausticRay>& rays = object_rays.rays;
  SpotLightSet set;
  set.rays = static_cast<int>(rays.size());
  set.trace_seconds = object_rays.seconds;
  RayRaster raster(bounds.center, settings.bundle.raster_half_size, settings.bundle.raster_resolution);
  std::vector<uint8_t> active(rays.size(), 1);
  for (const CausticRay& ray : rays) {
    raster.add(ray, 1.0);
    set.ray_energy += ray.weight;
  }
  double remaining = set.ray_energy;
  const double goal = (1.0 - settings.energy_coverage) * set.ray_energy;
  // A seed whose bundle cannot be fitted is retired; 16 failures in a row mean the rest of the light
  // field is not of spot light shape.
  int failures = 0;
  while (remaining > goal && static_cast<int>(set.lights.size()) < settings.max_lights && failures < 16) {
    const int cell = raster.richest_cell(1e-9 * set.ray_energy);
    if (cell < 0) break;
    ++set.seeds_tried;
    const Bundle bundle = grow_bundle(rays, active, raster, cell, settings.bundle);
    if (bundle.members.empty()) {
      raster.retire(cell);
      ++failures;
      continue;
    }
    const Fit fit = fit_spot_light(rays, bundle.members, bundle.axis, settings.fit);
    SpotLight light;
    light.origin = Vec3(fit.origin);
    light.axis = Vec3(bundle.axis.direction);
    set_plane_axes(light);
    light.profile = fit.profile;
    // The rays the spot light represents: those its rays follow within fit_tolerance and that cross
    // its plane within the square holding all but the outermost half percent of their energy (a ray
    // nearly parallel to the plane crosses it far out, where it would only stretch the image and
    // coarsen its texels). The others stay in the pool for a bundle of another axis.
    std::vector<std::tuple<double, uint32_t, double>> fitting;  // (square radius on the plane, ray, chord)
    double fitting_energy = 0.0;
    for (uint32_t index : bundle.members) {
      const RayOnPlane on = ray_on_plane(rays[index], bundle.axis, fit.ell, fit.profile);
      if (!on.valid || !(on.chord <= settings.fit_tolerance)) continue;
      const glm::dvec3 from = on.p - fit.origin;
      fitting.emplace_back(std::max(std::fabs(glm::dot(from, glm::dvec3(light.u))), std::fabs(glm::dot(from, glm::dvec3(light.v)))),
                           index, on.chord);
      fitting_energy += rays[index].weight;
    }
    std::sort(fitting.begin(), fitting.end());
    std::vector<uint32_t> kept;
    double energy = 0.0, misdirected = 0.0;
    for (const auto& [extent, index, chord] : fitting) {
      if (energy > 0.995 * fitting_energy) break;
      kept.push_back(index);
      energy += rays[index].weight;
      if (chord > kMisdirectedChord) misdirected += rays[index].weight;
    }
    std::sort(kept.begin(), kept.end());
    if (kept.empty()) {
      raster.retire(cell);
      ++failures;
      continue;
    }
    failures = 0;
    light.image = splat_intensity(rays, kept, light, settings.splat);
    for (uint32_t index : kept) {
      active[index] = 0;
      raster.add(rays[index], -1.0);
    }
    remaining -= energy;
    set.covered_energy += energy;
    set.misdirected_energy += misdirected;
    SpotLightRecord record;
    record.bundle_rays = static_cast<int>(bundle.members.size());
    record.kept_rays = static_cast<int>(kept.size());
    record.energy = energy;
    record.bundle_iterations = bundle.iterations;
    record.bundle_converged = bundle.converged;
    record.fit = fit;
    set.lights.push_back(std::move(light));
    set.records.push_back(record);
  }
  set.cluster_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return set;
}

}  // namespace causticbench::csl
