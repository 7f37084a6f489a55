#include "core/specular_tree.h"

#include <vector>

#include "core/optics.h"

namespace causticbench {

namespace {
struct Branch {
  Ray ray;
  Color energy;
  const Material* medium;  // the glass the branch travels in, if any
  int depth;
};
}  // namespace

void trace_specular_tree(const Tracer& tracer, const Ray& start, const Color& energy, const SpecularTreeSettings& settings,
                         SpecularTreeStats& stats, const std::function<void(const ExitRay&)>& on_exit) {
  const Scene& scene = *tracer.frame().scene;
  const float threshold = settings.min_energy * max_component(energy);
  stats.started += luminance(energy);
  std::vector<Branch> stack;
  stack.push_back(Branch{start, energy, nullptr, 0});
  while (!stack.empty()) {
    Branch branch = stack.back();
    stack.pop_back();
    SurfaceHit hit;
    ++stats.rays;
    if (!tracer.intersect(branch.ray, hit)) {
      if (branch.depth > 0) {
        on_exit(ExitRay{branch.ray.origin, branch.ray.direction, branch.energy, branch.depth});
        stats.exited += luminance(branch.energy);
      } else {
        stats.missed += luminance(branch.energy);
      }
      continue;
    }
    if (branch.medium) {
      const Color kept = branch.energy * glm::exp(-branch.medium->absorption * hit.t);
      stats.absorbed += luminance(branch.energy - kept);
      branch.energy = kept;
    }
    const Material& material = scene.objects[hit.object].material;
    if (material.receives_caustics() || !material.is_specular()) {
      stats.absorbed += luminance(branch.energy);
      continue;
    }
    if (branch.depth >= settings.max_depth) {
      stats.dropped += luminance(branch.energy);
      continue;
    }
    const bool from_outside = glm::dot(branch.ray.direction, hit.geometric_normal) < 0.0f;
    const Vec3 normal =
        glm::dot(branch.ray.direction, hit.shading_normal) < 0.0f ? hit.shading_normal : -hit.shading_normal;
    const float cos_incident = -glm::dot(branch.ray.direction, normal);
    // Children are pushed refraction first so that reflection is traced first.
    auto push = [&](const Vec3& direction, const Color& child_energy, const Material* medium) {
      if (max_component(child_energy) < threshold || max_component(child_energy) <= 0.0f) {
        stats.dropped += luminance(child_energy);
        return;
      }
      stack.push_back(Branch{tracer.spawn(hit, direction), child_energy, medium, branch.depth + 1});
    };
    if (material.kind == MaterialKind::glass) {
      const float eta = from_outside ? material.ior : 1.0f / material.ior;
      const float reflectance = fresnel_dielectric(cos_incident, eta);
      Vec3 transmitted;
      if (reflectance < 1.0f && refract(branch.ray.direction, normal, eta, transmitted)) {
        push(transmitted, branch.energy * (1.0f - reflectance), from_outside ? &material : nullptr);
        push(reflect(branch.ray.direction, normal), branch.energy * reflectance, branch.medium);
      } else {
        push(reflect(branch.ray.direction, normal), branch.energy, branch.medium);
      }
    } else {
      const Color reflected = branch.energy * material.mirror_reflectance(cos_incident);
      stats.absorbed += luminance(branch.energy - reflected);
      push(reflect(branch.ray.direction, normal), reflected, branch.medium);
    }
  }
}

}  // namespace causticbench
