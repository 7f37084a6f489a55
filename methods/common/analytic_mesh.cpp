#include "methods/common/analytic_mesh.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace causticbench {

namespace {

// A grid of (rows + 1) x segments vertices closed around the axis: vertex (row, k) at `position(row, k)`
// with normal `normal(row, k)`; quads between consecutive rows, wound so that the triangle normal
// agrees with the vertex normals (TriangleMesh::orient_by_normals fixes any that do not).
template <class Position, class Normal>
void add_band(TriangleMesh& mesh, int rows, int segments, Position position, Normal normal) {
  const uint32_t first = static_cast<uint32_t>(mesh.positions.size());
  for (int row = 0; row <= rows; ++row)
    for (int k = 0; k < segments; ++k) {
      mesh.positions.push_back(position(row, k));
      mesh.normals.push_back(normal(row, k));
    }
  auto index = [&](int row, int k) { return first + static_cast<uint32_t>(row * segments + (k % segments)); };
  for (int row = 0; row < rows; ++row)
    for (int k = 0; k < segments; ++k) {
      mesh.triangles.emplace_back(index(row, k), index(row + 1, k), index(row + 1, k + 1));
      mesh.triangles.emplace_back(index(row, k), index(row + 1, k + 1), index(row, k + 1));
    }
}

// A disk or annulus in the plane y = `y` between radii inner and outer (a centre vertex when inner is 0),
// facing `up` (+1 or -1).
void add_annulus(TriangleMesh& mesh, double y, double inner, double outer, int rows, int segments, float up) {
  const double step = 2.0 * kPiDouble / segments;
  auto ring_point = [&](int row, int k) {
    const double radius = inner + (outer - inner) * row / rows;
    return Vec3(static_cast<float>(radius * std::cos(k * step)), static_cast<float>(y), static_cast<float>(radius * std::sin(k * step)));
  };
  const Vec3 normal(0.0f, up, 0.0f);
  if (inner > 0.0) {
    add_band(mesh, rows, segments, ring_point, [&](int, int) { return normal; });
    return;
  }
  // The centre, then rings 1 .. rows.
  const uint32_t centre = static_cast<uint32_t>(mesh.positions.size());
  mesh.positions.push_back(Vec3(0.0f, static_cast<float>(y), 0.0f));
  mesh.normals.push_back(normal);
  const uint32_t first = centre + 1;
  add_band(mesh, rows - 1, segments, [&](int row, int k) { return ring_point(row + 1, k); }, [&](int, int) { return normal; });
  for (int k = 0; k < segments; ++k)
    mesh.triangles.emplace_back(centre, first + static_cast<uint32_t>(k), first + static_cast<uint32_t>((k + 1) % segments));
}

// A cylinder wall of radius r from y = 0 to `height`, its normals radial, outward (`out` +1) or inward.
void add_wall(TriangleMesh& mesh, double radius, double height, int rows, int segments, float out) {
  const double step = 2.0 * kPiDouble / segments;
  add_band(
      mesh, rows, segments,
      [&](int row, int k) {
        return Vec3(static_cast<float>(radius * std::cos(k * step)), static_cast<float>(height * row / rows),
                    static_cast<float>(radius * std::sin(k * step)));
      },
      [&](int, int k) { return out * Vec3(static_cast<float>(std::cos(k * step)), 0.0f, static_cast<float>(std::sin(k * step))); });
}

}  // namespace

TriangleMesh tessellate_analytic(const ShapeDesc& shape, int segments) {
  segments = std::max(3, segments);
  const int rows = std::max(1, segments / 8);
  const double step = 2.0 * kPiDouble / segments;
  TriangleMesh mesh;
  mesh.smooth = true;
  switch (shape.kind) {
    case ShapeKind::sphere: {
      // Latitude rings between the poles (one vertex each), segments / 2 bands.
      const int bands = std::max(2, segments / 2);
      const double r = shape.radius;
      auto direction = [&](int ring, int k) {
        const double polar = kPiDouble * ring / bands;
        return glm::dvec3(std::sin(polar) * std::cos(k * step), std::cos(polar), std::sin(polar) * std::sin(k * step));
      };
      const uint32_t north = 0;
      mesh.positions.push_back(Vec3(0.0f, static_cast<float>(r), 0.0f));
      mesh.normals.push_back(Vec3(0, 1, 0));
      add_band(mesh, bands - 2, segments, [&](int row, int k) { return Vec3(r * direction(row + 1, k)); },
               [&](int row, int k) { return Vec3(direction(row + 1, k)); });
      const uint32_t south = static_cast<uint32_t>(mesh.positions.size());
      mesh.positions.push_back(Vec3(0.0f, static_cast<float>(-r), 0.0f));
      mesh.normals.push_back(Vec3(0, -1, 0));
      const uint32_t last_ring = south - static_cast<uint32_t>(segments);
      for (int k = 0; k < segments; ++k) {
        const uint32_t a = 1 + static_cast<uint32_t>(k), b = 1 + static_cast<uint32_t>((k + 1) % segments);
        mesh.triangles.emplace_back(north, b, a);
        mesh.triangles.emplace_back(south, last_ring + static_cast<uint32_t>(k), last_ring + static_cast<uint32_t>((k + 1) % segments));
      }
      break;
    }
    case ShapeKind::disk: add_annulus(mesh, 0.0, 0.0, shape.radius, rows, segments, 1.0f); break;
    case ShapeKind::ring:
      add_wall(mesh, shape.radius, shape.height, rows, segments, 1.0f);
      if (shape.thickness > 0.0) {
        const double inner = shape.radius - shape.thickness;
        add_wall(mesh, inner, shape.height, rows, segments, -1.0f);
        add_annulus(mesh, shape.height, inner, shape.radius, 1, segments, 1.0f);
        add_annulus(mesh, 0.0, inner, shape.radius, 1, segments, -1.0f);
      }
      break;
    case ShapeKind::cup:
      add_wall(mesh, shape.radius, shape.height, rows, segments, 1.0f);
      add_annulus(mesh, 0.0, 0.0, shape.radius, rows, segments, 1.0f);
      break;
    case ShapeKind::paraboloid: {
      // y = (x^2 + z^2) / (4 f) up to the aperture radius, normals on the concave (upper) side.
      const double f = shape.focal_length;
      const int radial = std::max(1, segments / 4);
      const uint32_t centre = static_cast<uint32_t>(mesh.positions.size());
      mesh.positions.push_back(Vec3(0.0f));
      mesh.normals.push_back(Vec3(0, 1, 0));
      auto point = [&](int row, int k) {
        const double radius = shape.radius * (row + 1) / radial;
        return glm::dvec3(radius * std::cos(k * step), radius * radius / (4.0 * f), radius * std::sin(k * step));
      };
      add_band(mesh, radial - 1, segments, [&](int row, int k) { return Vec3(point(row, k)); },
               [&](int row, int k) {
                 const glm::dvec3 p = point(row, k);
                 return Vec3(glm::normalize(glm::dvec3(-2.0 * p.x, 4.0 * f, -2.0 * p.z)));
               });
      for (int k = 0; k < segments; ++k)
        mesh.triangles.emplace_back(centre, centre + 1 + static_cast<uint32_t>(k), centre + 1 + static_cast<uint32_t>((k + 1) % segments));
      break;
    }
    default: throw std::logic_error("tessellate_analytic: " + shape_kind_name(shape.kind) + " is not an analytic shape");
  }
  mesh.orient_by_normals();
  return mesh;
}

SurfaceMesh subdivide_flat(const SurfaceMesh& flat, int n) {
  if (n <= 1) return flat;
  SurfaceMesh cut;
  for (const glm::uvec3& triangle : flat.triangles) {
    const glm::dvec3 a = flat.positions[triangle.x], b = flat.positions[triangle.y], c = flat.positions[triangle.z];
    const glm::dvec3 normal = flat.normals[triangle.x];
    // The point at barycentric steps (i along a->b, j along a->c), i + j <= n.
    auto point = [&](int i, int j) { return a + (b - a) * (double(i) / n) + (c - a) * (double(j) / n); };
    auto add = [&](glm::dvec3 p, glm::dvec3 q, glm::dvec3 r) {
      const uint32_t first = static_cast<uint32_t>(cut.positions.size());
      for (const glm::dvec3& corner : {p, q, r}) {
        cut.positions.push_back(corner);
        cut.normals.push_back(normal);
      }
      cut.triangles.emplace_back(first, first + 1, first + 2);
    };
    for (int i = 0; i < n; ++i)
      for (int j = 0; i + j < n; ++j) {
        add(point(i, j), point(i + 1, j), point(i, j + 1));  // the winding of (a, b, c)
        if (i + j + 1 < n) add(point(i + 1, j), point(i + 1, j + 1), point(i, j + 1));
      }
  }
  return cut;
}

SurfaceMesh surface_mesh(const SceneFrame& frame, int object, int segments, bool subdivide_flat_solids) {
  const SceneObject& described = frame.scene->objects[static_cast<size_t>(object)];
  SurfaceMesh mesh;
  if (described.shape.is_analytic()) {
    const TriangleMesh local = tessellate_analytic(described.shape, segments);
    const Transform& transform = frame.transforms[static_cast<size_t>(object)];
    for (size_t i = 0; i < local.positions.size(); ++i) {
      mesh.positions.push_back(glm::dvec3(transform.point(local.positions[i])));
      mesh.normals.push_back(glm::normalize(glm::dvec3(transform.normal(local.normals[i]))));
    }
    mesh.triangles = local.triangles;
    return mesh;
  }
  const TriangleMesh& world = frame.world_meshes[static_cast<size_t>(object)];
  for (size_t i = 0; i < world.positions.size(); ++i) {
    mesh.positions.push_back(glm::dvec3(world.positions[i]));
    const bool smooth = world.smooth && i < world.normals.size();
    mesh.normals.push_back(smooth ? glm::normalize(glm::dvec3(world.normals[i])) : glm::dvec3(0.0));
  }
  mesh.triangles = world.triangles;
  if (!world.smooth) {
    // Flat shading: one normal per triangle, so that its vertices are not shared (each triangle a prism).
    SurfaceMesh flat;
    for (const glm::uvec3& triangle : world.triangles) {
      const glm::dvec3 p[3] = {mesh.positions[triangle.x], mesh.positions[triangle.y], mesh.positions[triangle.z]};
      const glm::dvec3 normal = glm::normalize(glm::cross(p[1] - p[0], p[2] - p[0]));
      const uint32_t first = static_cast<uint32_t>(flat.positions.size());
      for (const glm::dvec3& point : p) {
        flat.positions.push_back(point);
        flat.normals.push_back(normal);
      }
      flat.triangles.emplace_back(first, first + 1, first + 2);
    }
    const bool solid = described.shape.kind == ShapeKind::box || described.shape.kind == ShapeKind::prism;
    return subdivide_flat_solids && solid ? subdivide_flat(flat, std::max(1, segments / 4)) : flat;
  }
  return mesh;
}

}  // namespace causticbench
