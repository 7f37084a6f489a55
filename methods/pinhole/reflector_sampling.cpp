#include "methods/pinhole/reflector_sampling.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>
#include <unordered_set>

#include <fmt/format.h>

#include "core/errors.h"

namespace causticbench {

SamplingStrategy parse_sampling_strategy(const std::string& name) {
  if (name == "random") return SamplingStrategy::random;
  if (name == "grid") return SamplingStrategy::grid;
  if (name == "quantized_grid") return SamplingStrategy::quantized_grid;
  return SamplingStrategy::neighborhood;
}

namespace {

// One part of an analytic shape that can be sampled uniformly in object space.
struct Part {
  int surface;
  double area;
};

double paraboloid_area(double f, double radius) {
  return 8.0 * kPiDouble * f * f / 3.0 * (std::pow(1.0 + radius * radius / (4.0 * f * f), 1.5) - 1.0);
}

std::vector<Part> analytic_parts(const ShapeDesc& shape) {
  double r = shape.radius, h = shape.height;
  switch (shape.kind) {
    case ShapeKind::sphere: return {{0, 4.0 * kPiDouble * r * r}};
    case ShapeKind::disk: return {{0, kPiDouble * r * r}};
    case ShapeKind::ring:
      if (shape.thickness <= 0.0) return {{0, 2.0 * kPiDouble * r * h}};
      {
        double inner = r - shape.thickness;
        double annulus = kPiDouble * (r * r - inner * inner);
        return {{0, 2.0 * kPiDouble * r * h}, {1, 2.0 * kPiDouble * inner * h}, {2, annulus}, {3, annulus}};
      }
    case ShapeKind::cup: return {{0, 2.0 * kPiDouble * r * h}, {1, kPiDouble * r * r}};
    case ShapeKind::paraboloid: return {{0, paraboloid_area(shape.focal_length, r)}};
    default: return {};
  }
}

// A uniform object-space point on one part of an analytic shape.
glm::dvec3 sample_part(const ShapeDesc& shape, int surface, Random& random) {
  double u1 = random.uniform_double(), u2 = random.uniform_double();
  double r = shape.radius, h = shape.height, phi = 2.0 * kPiDouble * u2;
  auto annulus = [&](double inner, double outer, double y) {
    double radius = std::sqrt(inner * inner + u1 * (outer * outer - inner * inner));
    return glm::dvec3(radius * std::cos(phi), y, radius * std::sin(phi));
  };
  switch (shape.kind) {
    case ShapeKind::sphere: return glm::dvec3(sample_sphere(static_cast<float>(u1), static_cast<float>(u2))) * r;
    case ShapeKind::disk: return annulus(0.0, r, 0.0);
    case ShapeKind::ring:
    case ShapeKind::cup: {
      double inner = r - shape.thickness;
      if (shape.kind == ShapeKind::cup && surface == 1) return annulus(0.0, r, 0.0);
      if (surface == 2) return annulus(inner, r, h);
      if (surface == 3) return annulus(inner, r, 0.0);
      double radius = surface == 1 ? inner : r;
      return glm::dvec3(radius * std::cos(phi), u1 * h, radius * std::sin(phi));
    }
    case ShapeKind::paraboloid: {
      // Uniform in the disk, accepted in proportion to the surface element sqrt(1 + (r / 2f)^2).
      double f = shape.focal_length, max_element = std::sqrt(1.0 + r * r / (4.0 * f * f));
      while (true) {
        glm::dvec3 p = annulus(0.0, r, 0.0);
        double rho2 = p.x * p.x + p.z * p.z;
        if (random.uniform_double() * max_element <= std::sqrt(1.0 + rho2 / (4.0 * f * f))) {
          p.y = rho2 / (4.0 * f);
          return p;
        }
        u1 = random.uniform_double();
        phi = 2.0 * kPiDouble * random.uniform_double();
      }
    }
    default: return glm::dvec3(0.0);
  }
}

double area_scale(const Transform& transform) {
  // Area scales by |det|^(2/3) on average; exact for uniform scales.
  double determinant = std::abs(glm::determinant(glm::dmat3(transform.matrix)));
  return std::pow(determinant, 2.0 / 3.0);
}

struct CellKey {
  static uint64_t of(const Vec3& p, double inverse_cell) {
    auto c = [&](float v) { return static_cast<uint64_t>(static_cast<int64_t>(std::floor(v * inverse_cell)) & 0x1FFFFF); };
    return c(p.x) | (c(p.y) << 21) | (c(p.z) << 42);
  }
  static uint64_t of(int64_t x, int64_t y, int64_t z) {
    return static_cast<uint64_t>(x & 0x1FFFFF) | (static_cast<uint64_t>(y & 0x1FFFFF) << 21) |
           (static_cast<uint64_t>(z & 0x1FFFFF) << 42);
  }
};

// Grid stratification: the first dense point of every cell of size `cell`.
std::vector<size_t> grid_pick(const std::vector<SurfacePoint>& dense, double cell) {
  std::unordered_set<uint64_t> occupied;
  occupied.reserve(dense.size());
  std::vector<size_t> kept;
  double inverse = 1.0 / cell;
  for (size_t i = 0; i < dense.size(); ++i) {
    if (occupied.insert(CellKey::of(dense[i].position, inverse)).second) kept.push_back(i);
  }
  return kept;
}

// Neighbourhood stratification: greedily keep a point unless a kept point lies within `diameter`.
std::vector<size_t> neighborhood_pick(const std::vector<SurfacePoint>& dense, double diameter) {
  std::unordered_map<uint64_t, std::vector<uint32_t>> cells;
  cells.reserve(dense.size() / 2);
  std::vector<size_t> kept;
  double inverse = 1.0 / diameter;
  float diameter2 = static_cast<float>(diameter * diameter);
  for (size_t i = 0; i < dense.size(); ++i) {
    const Vec3& p = dense[i].position;
    int64_t cx = static_cast<int64_t>(std::floor(p.x * inverse)), cy = static_cast<int64_t>(std::floor(p.y * inverse)),
            cz = static_cast<int64_t>(std::floor(p.z * inverse));
    bool covered = false;
    for (int64_t dz = -1; dz <= 1 && !covered; ++dz) {
      for (int64_t dy = -1; dy <= 1 && !covered; ++dy) {
        for (int64_t dx = -1; dx <= 1 && !covered; ++dx) {
          auto it = cells.find(CellKey::of(cx + dx, cy + dy, cz + dz));
          if (it == cells.end()) continue;
          for (uint32_t j : it->second) {
            Vec3 offset = dense[j].position - p;
            if (glm::dot(offset, offset) < diameter2) {
              covered = true;
              break;
            }
          }
        }
      }
    }
    if (covered) continue;
    cells[CellKey::of(cx, cy, cz)].push_back(static_cast<uint32_t>(i));
    kept.push_back(i);
  }
  return kept;
}

// The scale (cell size or diameter) whose kept count is closest to the target: counts fall as the
// scale grows, so bisect on a log scale.
template <typename Pick>
std::vector<size_t> search_scale(const std::vector<SurfacePoint>& dense, size_t target, double guess, Pick pick,
                                 double& chosen) {
  double low = guess / 8.0, high = guess * 8.0;
  std::vector<size_t> best;
  double best_error = 1e300;
  for (int iteration = 0; iteration < 24; ++iteration) {
    double scale = std::sqrt(low * high);
    std::vector<size_t> kept = pick(dense, scale);
    bool too_many = kept.size() > target;
    double error = std::abs(static_cast<double>(kept.size()) - static_cast<double>(target));
    if (error < best_error) {
      best_error = error;
      best = std::move(kept);
      chosen = scale;
    }
    if (best_error <= 0.01 * static_cast<double>(target)) break;
    (too_many ? low : high) = scale;
  }
  return best;
}

double triangle_area(const TriangleMesh& mesh, const glm::uvec3& t) {
  return 0.5 * glm::length(glm::cross(mesh.positions[t.y] - mesh.positions[t.x], mesh.positions[t.z] - mesh.positions[t.x]));
}

}  // namespace

double object_area(const SceneFrame& frame, int object) {
  const SceneObject& scene_object = frame.scene->objects[object];
  if (scene_object.shape.is_analytic()) {
    double area = 0.0;
    for (const Part& part : analytic_parts(scene_object.shape)) area += part.area;
    return area * area_scale(frame.transforms[object]);
  }
  const TriangleMesh& mesh = frame.world_meshes[object];
  double area = 0.0;
  for (const glm::uvec3& t : mesh.triangles) area += triangle_area(mesh, t);
  return area;
}

std::vector<SurfacePoint> sample_surfaces(const SceneFrame& frame, const std::vector<int>& objects, size_t count,
                                          Random& random, double& total_area) {
  // Per-object samplers, built once: analytic parts by area (in object space; the transform scales
  // every part alike) or world-space triangles by area.
  std::vector<double> areas;
  std::vector<std::vector<Part>> parts(objects.size());
  std::vector<Distribution1D> part_choice(objects.size()), triangle_choice(objects.size());
  for (size_t i = 0; i < objects.size(); ++i) {
    const SceneObject& object = frame.scene->objects[objects[i]];
    std::vector<double> piece_areas;
    if (object.shape.is_analytic()) {
      parts[i] = analytic_parts(object.shape);
      for (const Part& part : parts[i]) piece_areas.push_back(part.area);
      part_choice[i] = Distribution1D(piece_areas);
      areas.push_back(part_choice[i].total() * area_scale(frame.transforms[objects[i]]));
    } else {
      const TriangleMesh& mesh = frame.world_meshes[objects[i]];
      for (const glm::uvec3& t : mesh.triangles) piece_areas.push_back(triangle_area(mesh, t));
      triangle_choice[i] = Distribution1D(piece_areas);
      areas.push_back(triangle_choice[i].total());
    }
  }
  Distribution1D object_choice(areas);
  total_area = object_choice.total();
  std::vector<SurfacePoint> points;
  if (total_area <= 0.0) return points;
  points.reserve(count);
  for (size_t n = 0; n < count; ++n) {
    double probability;
    size_t index = object_choice.sample(random.uniform_double(), probability);
    int object = objects[index];
    const SceneObject& scene_object = frame.scene->objects[object];
    const Transform& transform = frame.transforms[object];
    SurfacePoint point;
    point.object = object;
    if (scene_object.shape.is_analytic()) {
      int surface = parts[index][part_choice[index].sample(random.uniform_double(), probability)].surface;
      glm::dvec3 local = sample_part(scene_object.shape, surface, random);
      point.position = transform.point(Vec3(local));
      point.normal = transform.normal(Vec3(analytic_normal(scene_object.shape, surface, local)));
    } else {
      const TriangleMesh& mesh = frame.world_meshes[object];
      const glm::uvec3& t = mesh.triangles[triangle_choice[index].sample(random.uniform_double(), probability)];
      float u = random.uniform(), v = random.uniform();
      if (u + v > 1.0f) {
        u = 1.0f - u;
        v = 1.0f - v;
      }
      point.position = (1.0f - u - v) * mesh.positions[t.x] + u * mesh.positions[t.y] + v * mesh.positions[t.z];
      Vec3 flat = glm::normalize(glm::cross(mesh.positions[t.y] - mesh.positions[t.x], mesh.positions[t.z] - mesh.positions[t.x]));
      point.normal = mesh.smooth ? glm::normalize((1.0f - u - v) * mesh.normals[t.x] + u * mesh.normals[t.y] + v * mesh.normals[t.z])
                                 : flat;
    }
    points.push_back(point);
  }
  return points;
}

namespace {

bool is_two_sided(const ShapeDesc& shape) {
  switch (shape.kind) {
    case ShapeKind::quad:
    case ShapeKind::disk:
    case ShapeKind::cup:
    case ShapeKind::paraboloid:
    case ShapeKind::water: return true;
    case ShapeKind::ring: return shape.thickness <= 0.0;
    default: return false;
  }
}

}  // namespace

SampleSet sample_reflectors(const SceneFrame& frame, const std::vector<int>& objects, size_t target,
                            SamplingStrategy strategy, uint64_t seed, int oversampling) {
  SampleSet set;
  Random random(seed, 0x5eed0000ull + static_cast<uint64_t>(frame.frame * 1000.0));
  size_t dense_count = strategy == SamplingStrategy::random ? target : std::max<size_t>(20000, target * oversampling);
  set.dense = sample_surfaces(frame, objects, dense_count, random, set.total_area);
  if (set.dense.empty()) return set;
  std::vector<size_t> kept;
  double guess = std::sqrt(set.total_area / static_cast<double>(target));
  switch (strategy) {
    case SamplingStrategy::random:
      for (size_t i = 0; i < target; ++i) kept.push_back(i);
      break;
    case SamplingStrategy::grid:
    case SamplingStrategy::quantized_grid:
      kept = search_scale(set.dense, target, guess, grid_pick, set.cell_or_diameter);
      break;
    case SamplingStrategy::neighborhood:
      kept = search_scale(set.dense, target, guess, neighborhood_pick, set.cell_or_diameter);
      break;
  }
  set.spacing = std::sqrt(set.total_area / static_cast<double>(kept.size()));
  float area = static_cast<float>(set.total_area / static_cast<double>(kept.size()));
  for (size_t index : kept) {
    const SurfacePoint& point = set.dense[index];
    ReflectorSample sample;
    sample.position = point.position;
    sample.normal = point.normal;
    sample.object = point.object;
    sample.area = area;
    sample.two_sided = is_two_sided(frame.scene->objects[point.object].shape);
    if (strategy == SamplingStrategy::quantized_grid) {
      // Snapped to the centre of its cell: the displacement the paper warns about.
      double cell = set.cell_or_diameter;
      sample.position = Vec3((glm::floor(glm::dvec3(point.position) / cell) + 0.5) * cell);
    }
    orthonormal_basis(sample.normal, sample.direction_u, sample.direction_v);
    set.samples.push_back(sample);
  }
  return set;
}

void estimate_differentials(SampleSet& set, double radius) {
  if (set.samples.empty() || radius <= 0.0) return;
  double inverse = 1.0 / radius;
  std::unordered_map<uint64_t, std::vector<uint32_t>> cells;
  for (size_t i = 0; i < set.dense.size(); ++i) cells[CellKey::of(set.dense[i].position, inverse)].push_back(static_cast<uint32_t>(i));
  float radius2 = static_cast<float>(radius * radius);
  std::vector<std::pair<glm::dvec2, glm::dvec3>> neighbours;  // reused: one allocation, not one per sample
  for (ReflectorSample& sample : set.samples) {
    const Vec3 p = sample.position, n = sample.normal;
    Vec3 t, b;
    orthonormal_basis(n, t, b);
    // Centred least squares of n_i against (u_i, v_i).
    neighbours.clear();
    int64_t cx = static_cast<int64_t>(std::floor(p.x * inverse)), cy = static_cast<int64_t>(std::floor(p.y * inverse)),
            cz = static_cast<int64_t>(std::floor(p.z * inverse));
    for (int64_t dz = -1; dz <= 1; ++dz) {
      for (int64_t dy = -1; dy <= 1; ++dy) {
        for (int64_t dx = -1; dx <= 1; ++dx) {
          auto it = cells.find(CellKey::of(cx + dx, cy + dy, cz + dz));
          if (it == cells.end()) continue;
          for (uint32_t j : it->second) {
            const SurfacePoint& q = set.dense[j];
            Vec3 offset = q.position - p;
            if (q.object != sample.object || glm::dot(offset, offset) > radius2 || glm::dot(q.normal, n) < 0.5f) continue;
            neighbours.push_back({glm::dvec2(glm::dot(offset, t), glm::dot(offset, b)), glm::dvec3(q.normal)});
          }
        }
      }
    }
    if (neighbours.size() < 6) continue;  // too few to fit: treated as locally flat
    glm::dvec2 mean_uv(0.0);
    glm::dvec3 mean_n(0.0);
    for (const auto& [uv, normal] : neighbours) {
      mean_uv += uv;
      mean_n += normal;
    }
    mean_uv /= static_cast<double>(neighbours.size());
    mean_n /= static_cast<double>(neighbours.size());
    double suu = 0, suv = 0, svv = 0;
    glm::dvec3 sun(0.0), svn(0.0);
    for (const auto& [uv, normal] : neighbours) {
      glm::dvec2 d = uv - mean_uv;
      glm::dvec3 dn = normal - mean_n;
      suu += d.x * d.x;
      suv += d.x * d.y;
      svv += d.y * d.y;
      sun += d.x * dn;
      svn += d.y * dn;
    }
    double determinant = suu * svv - suv * suv;
    if (std::abs(determinant) < 1e-30) continue;
    glm::dvec3 dndu = (svv * sun - suv * svn) / determinant;
    glm::dvec3 dndv = (suu * svn - suv * sun) / determinant;
    // Symmetrised shape operator in (t, b) and its eigenvectors: the principal directions.
    double s11 = glm::dot(glm::dvec3(t), dndu), s22 = glm::dot(glm::dvec3(b), dndv);
    double s12 = 0.5 * (glm::dot(glm::dvec3(t), dndv) + glm::dot(glm::dvec3(b), dndu));
    double angle = 0.5 * std::atan2(2.0 * s12, s11 - s22);
    double c = std::cos(angle), s = std::sin(angle);
    sample.direction_u = Vec3(c * glm::dvec3(t) + s * glm::dvec3(b));
    sample.direction_v = Vec3(-s * glm::dvec3(t) + c * glm::dvec3(b));
    sample.normal_derivative_u = Vec3(c * dndu + s * dndv);
    sample.normal_derivative_v = Vec3(-s * dndu + c * dndv);
    sample.curvature_u = static_cast<float>(c * c * s11 + 2.0 * c * s * s12 + s * s * s22);
    sample.curvature_v = static_cast<float>(s * s * s11 - 2.0 * c * s * s12 + c * c * s22);
  }
}

}  // namespace causticbench
