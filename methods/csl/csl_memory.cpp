// What csl's knobs cost in memory (CausticMethod::knob_memory), for the check before any work starts.
// Each term was measured on the glass sphere at 24x18 (issue 30, defect 4; tests/test_memory_cost.cpp):
//   tracing a light direction: every caustic ray (40 bytes) three times over while the rows are copied
//     into one vector, 120 bytes a ray; R = rho x rays_per_side^2 rays, rho the caustic rays per grid
//     ray, taken from a pilot of 64 x 64 rays (2.6 on the glass sphere at min_energy 0.01), x 1.25;
//   the raster of the rays' lines: 9 bytes a cell (raster_resolution^3);
//   the fit of a bundle: about 700 bytes a fit ray (Ceres' residual blocks and dense Jacobian), at most
//     min(fit_rays, R) rays (an upper bound: the largest bundle held about R/2, 2.3x below it);
//   the images kept: texels x channels x (2 bytes, uint16; 4, float32) per spot light, three copies of
//     one while it is made;
//   a moving light: min(threads, corner directions) sets at once, and min(threads, edges) tracking
//     traces of tracking_rays_per_side^2 grid rays at once.
// The one term that is not a bound: the count of spot lights a direction keeps is the data's (4 to 13
// on the glass sphere at distance_threshold 0.3, 4.5 to 8.5 on average over the README's scenes, 35 at
// 0.1); max_csls (64 by default) would be 11x over and refuse ordinary runs on small machines. The
// estimate takes min(max_csls, 8) a direction, the upper end of the averages at the default
// distance_threshold, and the message says it is a typical count.
#include <algorithm>
#include <cmath>
#include <set>

#include <fmt/format.h>

#include "core/errors.h"
#include "core/parallel.h"
#include "methods/csl/csl.h"
#include "methods/csl/object_rays.h"

namespace causticbench {

using namespace csl;

namespace {

constexpr double kBytesPerTracedRay = 120.0;
constexpr double kBytesPerRasterCell = 9.0;
constexpr double kBytesPerFitRay = 700.0;
constexpr double kTypicalSpotLightsPerDirection = 8.0;

}  // namespace

std::vector<MemoryTerm> CslMethod::knob_memory(const PrepareContext& context, const ParamSet& knobs) const {
  std::unique_ptr<SphericalMesh> mesh;
  const Plan plan = make_plan(context, knobs, mesh);
  const double per_side = static_cast<double>(knobs.integer("rays_per_side"));
  const double raster = std::pow(static_cast<double>(knobs.integer("raster_resolution")), 3.0);
  const std::string size = knobs.text("image_size");
  const double side = size == "auto" ? 512.0 : std::stod(size);
  const double texel_bytes = knobs.text("precision") == "float32" ? 4.0 : 2.0;
  const double lights = std::min(static_cast<double>(knobs.integer("max_csls")), kTypicalSpotLightsPerDirection);
  const double threads = std::max(1, ThreadLimit::current());
  MemoryTerm tracing{{"rays_per_side", "raster_resolution", "fit_rays"}, 0.0, ""};
  MemoryTerm tracking{{"tracking_rays_per_side"}, 0.0, ""};
  MemoryTerm images{{"light_subdivision", "image_size", "max_csls"}, 0.0, ""};
  std::vector<std::string> image_parts;
  for (size_t i = 0; i < plan.objects.size(); ++i) {
    const SceneFrame frame(plan.alone[i], 0.0);
    const Tracer tracer(frame);
    // The pilot: caustic rays per grid ray, and whether the object colours the light (three channels).
    const Vec3 direction = plan.dynamic[i] ? (plan.dynamic[i]->directions.empty() ? Vec3(0.0f, 1.0f, 0.0f)
                                                                                  : plan.dynamic[i]->directions.front())
                          : plan.static_directions[i].empty() ? Vec3(0.0f, 1.0f, 0.0f)
                                                              : plan.static_directions[i].front();
    SpecularTreeSettings tree;
    tree.min_energy = static_cast<float>(knobs.real("min_energy"));
    const ObjectRays pilot = trace_object_rays(tracer, plan.objects[i].bounds, direction, 64, tree);
    const double rho = 1.25 * static_cast<double>(pilot.rays.size()) / (64.0 * 64.0);
    double channels = 1.0;
    for (const CausticRay& ray : pilot.rays)
      if (std::fabs(ray.energy.r - ray.energy.g) > 1e-5f * max_component(ray.energy) ||
          std::fabs(ray.energy.r - ray.energy.b) > 1e-5f * max_component(ray.energy))
        channels = 3.0;
    const double rays = rho * per_side * per_side;
    const double image = side * side * channels * texel_bytes + 16.0 * channels * (2.0 * side + 1.0) + 328.0;
    double directions = static_cast<double>(plan.static_directions[i].size()), at_once = 1.0, edges = 0.0, facets = 0.0;
    if (plan.dynamic[i]) {
      std::set<uint32_t> corners;
      std::set<std::pair<uint32_t, uint32_t>> sides;
      for (uint32_t t : plan.facets[i]) {
        const auto& triangle = mesh->triangles()[t];
        for (int c = 0; c < 3; ++c) {
          corners.insert(triangle[c]);
          sides.insert({std::min(triangle[c], triangle[(c + 1) % 3]), std::max(triangle[c], triangle[(c + 1) % 3])});
        }
      }
      directions = static_cast<double>(corners.size());
      edges = static_cast<double>(sides.size());
      facets = static_cast<double>(plan.facets[i].size());
      at_once = std::min(threads, directions);
      const double tracking_side = static_cast<double>(knobs.integer("tracking_rays_per_side"));
      tracking.bytes = std::max(tracking.bytes, std::min(threads, edges) * kBytesPerTracedRay * rho * tracking_side * tracking_side);
    }
    // Objects are built one after another: the largest transient, the sum of what is kept.
    const double transient = at_once * (kBytesPerTracedRay * rays + kBytesPerRasterCell * raster +
                                        kBytesPerFitRay * std::min(static_cast<double>(knobs.integer("fit_rays")), rays) +
                                        3.0 * side * side * channels * 4.0);
    tracing.bytes = std::max(tracing.bytes, transient);
    const double kept = directions * lights * image + edges * 2.0 * lights * 408.0 + facets * 3.0 * lights * 16.0;
    images.bytes += kept * (knobs.text("backend") == "vulkan" ? 4.0 : 1.0);
    image_parts.push_back(fmt::format("'{}': {:.0f} direction{} x {:.0f} spot lights x {:.0f}^2 texels x {:.0f} channel{}",
                                      plan.objects[i].name, directions, directions == 1.0 ? "" : "s", lights, side,
                                      channels, channels == 1.0 ? "" : "s"));
    if (i == 0 || transient >= tracing.bytes) {
      tracing.formula = fmt::format("'{}': {:.0f} set{} at once x ({:.3g} rays x {:.0f} bytes + {:.0f}^3 raster cells x {:.0f} "
                                    "bytes + fit and image), {:.2f} caustic rays a grid ray",
                                    plan.objects[i].name, at_once, at_once == 1.0 ? "" : "s", rays, kBytesPerTracedRay,
                                    std::cbrt(raster), kBytesPerRasterCell, rho);
    }
  }
  if (knobs.text("backend") == "vulkan") images.bytes += 64.0 * 1048576.0;
  images.formula = fmt::format("{} (the spot lights a direction keeps: min(max_csls, {:.0f}), a typical count, not a bound)",
                               join(image_parts, "; "), kTypicalSpotLightsPerDirection);
  tracking.formula = fmt::format("min(threads, edges) tracking traces of {}^2 grid rays at once",
                                 knobs.integer("tracking_rays_per_side"));
  std::vector<MemoryTerm> terms = {tracing, images};
  if (tracking.bytes > 0.0) terms.push_back(tracking);
  return terms;
}

}  // namespace causticbench
