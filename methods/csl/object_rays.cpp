#include "methods/csl/object_rays.h"

#include <chrono>

#include "core/parallel.h"

namespace causticbench::csl {

ObjectRays trace_object_rays(const Tracer& tracer, const BoundingSphere& bounds, const Vec3& to_light, int rays_per_side,
                             const SpecularTreeSettings& settings) {
  const auto start = std::chrono::steady_clock::now();
  ObjectRays result;
  Vec3 t, b;
  orthonormal_basis(to_light, t, b);
  const double side = 2.0 * bounds.radius;
  result.spacing = side / rays_per_side;
  const float cell_area = static_cast<float>(result.spacing * result.spacing);
  // One row of the grid per task, concatenated in row order: the same rays for any thread count.
  std::vector<std::vector<CausticRay>> rows(rays_per_side);
  std::vector<SpecularTreeStats> row_stats(rays_per_side);
  const float back = bounds.radius * 1.01f + 1e-3f;
  parallel_blocks(static_cast<size_t>(rays_per_side), 1, [&](size_t begin, size_t end, size_t) {
    for (size_t row = begin; row < end; ++row) {
      const float y = static_cast<float>(-bounds.radius + (row + 0.5) * result.spacing);
      for (int column = 0; column < rays_per_side; ++column) {
        const float x = static_cast<float>(-bounds.radius + (column + 0.5) * result.spacing);
        if (x * x + y * y > bounds.radius * bounds.radius) continue;  // outside the sphere's shadow: misses
        Ray ray;
        ray.origin = bounds.center + x * t + y * b + back * to_light;
        ray.direction = -to_light;
        SpecularTreeStats stats;
        trace_specular_tree(tracer, ray, Color(cell_area), settings, stats, [&](const ExitRay& exit) {
          rows[row].push_back(CausticRay{exit.origin, exit.direction, exit.energy, luminance(exit.energy)});
        });
        // Only the rays that met something entered it.
        if (stats.missed == 0.0) {
          row_stats[row].add(stats);
        }
      }
    }
  });
  for (int row = 0; row < rays_per_side; ++row) {
    result.rays.insert(result.rays.end(), rows[row].begin(), rows[row].end());
    result.stats.add(row_stats[row]);
  }
  result.entering = result.stats.started;
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace causticbench::csl
