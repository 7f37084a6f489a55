#include "core/shape.h"

#include <filesystem>

#include <fmt/format.h>

#include "core/assets.h"
#include "core/mesh_file.h"

namespace causticbench {

namespace {

const std::vector<std::string> kShapeNames = {"quad",  "disk", "sphere", "ring",       "cup",  "torus",
                                              "box",   "prism", "paraboloid", "water", "mesh"};

// Smallest root of a t^2 + b t + c = 0 inside (t_min, t_max) that passes `accept`.
template <typename Accept>
bool solve_quadratic(double a, double b, double c, double t_min, double t_max, Accept accept, double& t_out) {
  double roots[2];
  int count = 0;
  if (std::abs(a) < 1e-300) {
    if (std::abs(b) < 1e-300) return false;
    roots[count++] = -c / b;
  } else {
    double discriminant = b * b - 4.0 * a * c;
    if (discriminant < 0.0) return false;
    double root = std::sqrt(discriminant);
    // Numerically stable form (no cancellation between -b and the root).
    double q = -0.5 * (b + std::copysign(root, b));
    double r0 = q / a;
    double r1 = q != 0.0 ? c / q : r0;
    roots[count++] = std::min(r0, r1);
    roots[count++] = std::max(r0, r1);
  }
  for (int i = 0; i < count; ++i) {
    if (roots[i] > t_min && roots[i] < t_max && accept(roots[i])) {
      t_out = roots[i];
      return true;
    }
  }
  return false;
}

bool hit_cylinder(double radius, double y0, double y1, const glm::dvec3& o, const glm::dvec3& d, double t_min,
                  double t_max, double& t) {
  double a = d.x * d.x + d.z * d.z;
  double b = 2.0 * (o.x * d.x + o.z * d.z);
  double c = o.x * o.x + o.z * o.z - radius * radius;
  return solve_quadratic(a, b, c, t_min, t_max, [&](double root) {
    double y = o.y + root * d.y;
    return y >= y0 && y <= y1;
  }, t);
}

bool hit_annulus(double y, double inner, double outer, const glm::dvec3& o, const glm::dvec3& d, double t_min,
                 double t_max, double& t) {
  if (d.y == 0.0) return false;
  double root = (y - o.y) / d.y;
  if (!(root > t_min && root < t_max)) return false;
  double x = o.x + root * d.x, z = o.z + root * d.z;
  double r2 = x * x + z * z;
  if (r2 > outer * outer || r2 < inner * inner) return false;
  t = root;
  return true;
}

struct Closest {
  double t_max;
  AnalyticHit hit;
  bool found = false;
  // t by reference: it is read after the solver call that fills it (argument order is unspecified).
  void offer(bool hit_found, const double& t, int surface) {
    if (hit_found && t < t_max) {
      t_max = t;
      hit = AnalyticHit{t, surface};
      found = true;
    }
  }
};

void add_quad(TriangleMesh& mesh, Vec3 a, Vec3 b, Vec3 c, Vec3 d) {
  uint32_t base = static_cast<uint32_t>(mesh.positions.size());
  for (const Vec3& p : {a, b, c, d}) mesh.positions.push_back(p);
  mesh.triangles.emplace_back(base, base + 1, base + 2);
  mesh.triangles.emplace_back(base, base + 2, base + 3);
}

void orient_outward_from(TriangleMesh& mesh, const Vec3& inside) {
  for (glm::uvec3& tri : mesh.triangles) {
    Vec3 p0 = mesh.positions[tri.x], p1 = mesh.positions[tri.y], p2 = mesh.positions[tri.z];
    Vec3 normal = glm::cross(p1 - p0, p2 - p0);
    if (glm::dot(normal, (p0 + p1 + p2) / 3.0f - inside) < 0.0f) std::swap(tri.y, tri.z);
  }
}

}  // namespace

void TriangleMesh::orient_by_normals() {
  if (normals.size() != positions.size()) return;
  for (glm::uvec3& tri : triangles) {
    Vec3 winding = glm::cross(positions[tri.y] - positions[tri.x], positions[tri.z] - positions[tri.x]);
    Vec3 average = normals[tri.x] + normals[tri.y] + normals[tri.z];
    if (glm::dot(winding, average) < 0.0f) std::swap(tri.y, tri.z);
  }
}

void TriangleMesh::compute_flat_normals() {
  // Flat meshes keep one normal per vertex only for orientation; shading uses the winding normal.
  normals.assign(positions.size(), Vec3(0.0f));
  for (const glm::uvec3& tri : triangles) {
    Vec3 n = glm::cross(positions[tri.y] - positions[tri.x], positions[tri.z] - positions[tri.x]);
    normals[tri.x] += n;
    normals[tri.y] += n;
    normals[tri.z] += n;
  }
  for (Vec3& n : normals) n = glm::length(n) > 0.0f ? glm::normalize(n) : Vec3(0, 1, 0);
}

bool ShapeDesc::is_analytic() const {
  switch (kind) {
    case ShapeKind::disk:
    case ShapeKind::sphere:
    case ShapeKind::ring:
    case ShapeKind::cup:
    case ShapeKind::paraboloid: return true;
    default: return false;
  }
}

bool ShapeDesc::changes_with_frame() const {
  if (kind != ShapeKind::water) return false;
  for (const WaterWave& wave : waves) {
    if (wave.phase_per_frame_degrees != 0.0) return true;
  }
  return false;
}

std::string shape_kind_name(ShapeKind kind) { return kShapeNames[static_cast<size_t>(kind)]; }
const std::vector<std::string>& shape_kind_names() { return kShapeNames; }

ShapeDesc read_shape(const ConfigNode& node, const std::string& scene_folder) {
  ShapeDesc shape;
  std::string type = node.choice("type", kShapeNames);
  for (size_t i = 0; i < kShapeNames.size(); ++i) {
    if (kShapeNames[i] == type) shape.kind = static_cast<ShapeKind>(i);
  }
  const double big = 1e6, tiny = 1e-9;
  switch (shape.kind) {
    case ShapeKind::quad: {
      std::vector<double> size = node.numbers("size", 2, tiny, big);
      shape.size = {size[0], size[1]};
      break;
    }
    case ShapeKind::disk:
    case ShapeKind::sphere: shape.radius = node.number("radius", tiny, big); break;
    case ShapeKind::ring:
      shape.radius = node.number("radius", tiny, big);
      shape.height = node.number("height", tiny, big);
      shape.thickness = node.number_or("thickness", 0.0, 0.0, shape.radius * 0.999);
      break;
    case ShapeKind::cup:
      shape.radius = node.number("radius", tiny, big);
      shape.height = node.number("height", tiny, big);
      break;
    case ShapeKind::torus: {
      shape.major_radius = node.number("major_radius", tiny, big);
      shape.minor_radius = node.number("minor_radius", tiny, shape.major_radius);
      if (node.has("segments")) {
        std::vector<double> segments = node.numbers("segments", 2, 3, 8192);
        shape.segments = {static_cast<int>(segments[0]), static_cast<int>(segments[1])};
      }
      break;
    }
    case ShapeKind::box: {
      std::vector<double> size = node.numbers("size", 3, tiny, big);
      shape.box_size = {size[0], size[1], size[2]};
      break;
    }
    case ShapeKind::prism:
      shape.side = node.number("side", tiny, big);
      shape.length = node.number("length", tiny, big);
      break;
    case ShapeKind::paraboloid:
      shape.focal_length = node.number("focal_length", tiny, big);
      shape.radius = node.number("radius", tiny, big);
      break;
    case ShapeKind::water: {
      std::vector<double> size = node.numbers("size", 2, tiny, big);
      shape.size = {size[0], size[1]};
      if (node.has("resolution")) {
        std::vector<double> resolution = node.numbers("resolution", 2, 1, 4096);
        shape.resolution = {static_cast<int>(resolution[0]), static_cast<int>(resolution[1])};
      }
      if (std::optional<ConfigNode> waves = node.optional_child("waves")) {
        for (size_t i = 0; i < waves->size(); ++i) {
          ConfigNode wave_node = waves->at(i);
          WaterWave wave;
          wave.amplitude = wave_node.number("amplitude", 0.0, big);
          wave.wavelength = wave_node.number("wavelength", tiny, big);
          wave.direction_degrees = wave_node.number_or("direction_degrees", 0.0, -360.0, 360.0);
          wave.phase_degrees = wave_node.number_or("phase_degrees", 0.0, -1e6, 1e6);
          wave.phase_per_frame_degrees = wave_node.number_or("phase_per_frame_degrees", 0.0, -1e6, 1e6);
          wave_node.finish();
          shape.waves.push_back(wave);
        }
      }
      break;
    }
    case ShapeKind::mesh: {
      shape.asset = node.string("asset");
      bool smooth = node.boolean_or("smooth_normals", true);
      double fit_size = node.number_or("fit_size", 0.0, 0.0, big);
      std::string path = resolve_asset(shape.asset, AssetKind{"mesh", {".obj", ".ply", ".stl"}}, scene_folder,
                                       node.location_of("asset"));
      shape.mesh = load_mesh(path, smooth, fit_size, node.location_of("asset"));
      break;
    }
  }
  node.finish();
  return shape;
}

double water_height(const ShapeDesc& shape, double x, double z, double frame, double* dh_dx, double* dh_dz) {
  double height = 0.0, gx = 0.0, gz = 0.0;
  for (const WaterWave& wave : shape.waves) {
    double k = 2.0 * kPiDouble / wave.wavelength;
    double angle = wave.direction_degrees * kPiDouble / 180.0;
    double dx = std::cos(angle), dz = std::sin(angle);
    double phase = (wave.phase_degrees + frame * wave.phase_per_frame_degrees) * kPiDouble / 180.0;
    double argument = k * (x * dx + z * dz) + phase;
    height += wave.amplitude * std::sin(argument);
    double slope = wave.amplitude * k * std::cos(argument);
    gx += slope * dx;
    gz += slope * dz;
  }
  if (dh_dx) *dh_dx = gx;
  if (dh_dz) *dh_dz = gz;
  return height;
}

TriangleMesh tessellate(const ShapeDesc& shape, double frame) {
  TriangleMesh mesh;
  switch (shape.kind) {
    case ShapeKind::quad: {
      float hx = static_cast<float>(shape.size.x * 0.5), hz = static_cast<float>(shape.size.y * 0.5);
      add_quad(mesh, Vec3(-hx, 0, -hz), Vec3(-hx, 0, hz), Vec3(hx, 0, hz), Vec3(hx, 0, -hz));
      mesh.compute_flat_normals();
      break;
    }
    case ShapeKind::box: {
      Vec3 h = Vec3(shape.box_size * 0.5);
      for (int axis = 0; axis < 3; ++axis) {
        for (float sign : {-1.0f, 1.0f}) {
          Vec3 normal(0.0f), u(0.0f), v(0.0f);
          normal[axis] = sign;
          u[(axis + 1) % 3] = h[(axis + 1) % 3];
          v[(axis + 2) % 3] = h[(axis + 2) % 3];
          Vec3 center = normal * h[axis];
          add_quad(mesh, center - u - v, center + u - v, center + u + v, center - u + v);
        }
      }
      orient_outward_from(mesh, Vec3(0.0f));
      mesh.compute_flat_normals();
      break;
    }
    case ShapeKind::prism: {
      float circumradius = static_cast<float>(shape.side / std::sqrt(3.0));
      float half_length = static_cast<float>(shape.length * 0.5);
      Vec3 corner[3];
      for (int i = 0; i < 3; ++i) {
        float angle = kPi / 2.0f + i * 2.0f * kPi / 3.0f;
        corner[i] = Vec3(circumradius * std::cos(angle), circumradius * std::sin(angle), 0.0f);
      }
      Vec3 front(0, 0, half_length);
      for (float sign : {-1.0f, 1.0f}) {
        uint32_t base = static_cast<uint32_t>(mesh.positions.size());
        for (int i = 0; i < 3; ++i) mesh.positions.push_back(corner[i] + sign * front);
        mesh.triangles.emplace_back(base, base + 1, base + 2);
      }
      for (int i = 0; i < 3; ++i) {
        Vec3 a = corner[i], b = corner[(i + 1) % 3];
        add_quad(mesh, a - front, b - front, b + front, a + front);
      }
      orient_outward_from(mesh, Vec3(0.0f));
      mesh.compute_flat_normals();
      break;
    }
    case ShapeKind::torus: {
      int nu = shape.segments.x, nv = shape.segments.y;
      double big_r = shape.major_radius, small_r = shape.minor_radius;
      for (int i = 0; i < nu; ++i) {
        double theta = 2.0 * kPiDouble * i / nu;
        for (int j = 0; j < nv; ++j) {
          double phi = 2.0 * kPiDouble * j / nv;
          glm::dvec3 normal(std::cos(phi) * std::cos(theta), std::sin(phi), std::cos(phi) * std::sin(theta));
          glm::dvec3 center(big_r * std::cos(theta), 0.0, big_r * std::sin(theta));
          mesh.positions.push_back(Vec3(center + small_r * normal));
          mesh.normals.push_back(Vec3(normal));
        }
      }
      for (int i = 0; i < nu; ++i) {
        for (int j = 0; j < nv; ++j) {
          uint32_t a = i * nv + j, b = ((i + 1) % nu) * nv + j, c = ((i + 1) % nu) * nv + (j + 1) % nv,
                   d = i * nv + (j + 1) % nv;
          mesh.triangles.emplace_back(a, b, c);
          mesh.triangles.emplace_back(a, c, d);
        }
      }
      mesh.smooth = true;
      mesh.orient_by_normals();
      break;
    }
    case ShapeKind::water: {
      int nx = shape.resolution.x, nz = shape.resolution.y;
      for (int j = 0; j <= nz; ++j) {
        for (int i = 0; i <= nx; ++i) {
          double x = (static_cast<double>(i) / nx - 0.5) * shape.size.x;
          double z = (static_cast<double>(j) / nz - 0.5) * shape.size.y;
          double gx, gz;
          double y = water_height(shape, x, z, frame, &gx, &gz);
          mesh.positions.emplace_back(x, y, z);
          mesh.normals.push_back(Vec3(glm::normalize(glm::dvec3(-gx, 1.0, -gz))));
        }
      }
      for (int j = 0; j < nz; ++j) {
        for (int i = 0; i < nx; ++i) {
          uint32_t a = j * (nx + 1) + i, b = a + 1, c = a + nx + 2, d = a + nx + 1;
          mesh.triangles.emplace_back(a, b, c);
          mesh.triangles.emplace_back(a, c, d);
        }
      }
      mesh.smooth = true;
      mesh.orient_by_normals();
      break;
    }
    case ShapeKind::mesh: mesh = *shape.mesh; break;
    default: break;
  }
  return mesh;
}

bool intersect_analytic(const ShapeDesc& shape, const glm::dvec3& o, const glm::dvec3& d, double t_min, double t_max,
                        AnalyticHit& hit) {
  Closest closest{t_max, AnalyticHit{}, false};
  double t = 0.0;
  switch (shape.kind) {
    case ShapeKind::sphere: {
      double a = glm::dot(d, d), b = 2.0 * glm::dot(o, d), c = glm::dot(o, o) - shape.radius * shape.radius;
      closest.offer(solve_quadratic(a, b, c, t_min, t_max, [](double) { return true; }, t), t, 0);
      break;
    }
    case ShapeKind::disk: closest.offer(hit_annulus(0.0, 0.0, shape.radius, o, d, t_min, t_max, t), t, 0); break;
    case ShapeKind::ring:
      closest.offer(hit_cylinder(shape.radius, 0.0, shape.height, o, d, t_min, closest.t_max, t), t, 0);
      if (shape.thickness > 0.0) {
        double inner = shape.radius - shape.thickness;
        closest.offer(hit_cylinder(inner, 0.0, shape.height, o, d, t_min, closest.t_max, t), t, 1);
        closest.offer(hit_annulus(shape.height, inner, shape.radius, o, d, t_min, closest.t_max, t), t, 2);
        closest.offer(hit_annulus(0.0, inner, shape.radius, o, d, t_min, closest.t_max, t), t, 3);
      }
      break;
    case ShapeKind::cup:
      closest.offer(hit_cylinder(shape.radius, 0.0, shape.height, o, d, t_min, closest.t_max, t), t, 0);
      closest.offer(hit_annulus(0.0, 0.0, shape.radius, o, d, t_min, closest.t_max, t), t, 1);
      break;
    case ShapeKind::paraboloid: {
      double f4 = 4.0 * shape.focal_length;
      double a = d.x * d.x + d.z * d.z;
      double b = 2.0 * (o.x * d.x + o.z * d.z) - f4 * d.y;
      double c = o.x * o.x + o.z * o.z - f4 * o.y;
      double r2max = shape.radius * shape.radius;
      closest.offer(solve_quadratic(a, b, c, t_min, t_max, [&](double root) {
        double x = o.x + root * d.x, z = o.z + root * d.z;
        return x * x + z * z <= r2max;
      }, t), t, 0);
      break;
    }
    default: break;
  }
  if (closest.found) hit = closest.hit;
  return closest.found;
}

AffineNormal analytic_normal_field(const ShapeDesc& shape, int surface) {
  AffineNormal field;
  const glm::dmat3 radial(glm::dvec3(1, 0, 0), glm::dvec3(0, 0, 0), glm::dvec3(0, 0, 1));  // (x, 0, z)
  switch (shape.kind) {
    case ShapeKind::sphere: field.gradient = glm::dmat3(1.0); break;
    case ShapeKind::ring:
    case ShapeKind::cup:
      if ((shape.kind == ShapeKind::cup && surface == 1) || surface == 2) {
        field.offset = glm::dvec3(0, 1, 0);
      } else if (surface == 3) {
        field.offset = glm::dvec3(0, -1, 0);
      } else {
        field.gradient = surface == 1 ? -radial : radial;  // a solid ring's inner wall faces the axis
      }
      break;
    case ShapeKind::paraboloid:
      // Normal of the concave (upper) side: the side that focuses light coming from above.
      field.gradient = -2.0 * radial;
      field.offset = glm::dvec3(0.0, 4.0 * shape.focal_length, 0.0);
      break;
    default: field.offset = glm::dvec3(0, 1, 0); break;  // a disk, and any flat shape
  }
  return field;
}

glm::dvec3 analytic_normal(const ShapeDesc& shape, int surface, const glm::dvec3& p) {
  const AffineNormal field = analytic_normal_field(shape, surface);
  return glm::normalize(field.gradient * p + field.offset);
}

void analytic_bounds(const ShapeDesc& shape, glm::dvec3& lower, glm::dvec3& upper) {
  double r = shape.radius;
  switch (shape.kind) {
    case ShapeKind::sphere: lower = glm::dvec3(-r); upper = glm::dvec3(r); break;
    case ShapeKind::disk: lower = glm::dvec3(-r, 0, -r); upper = glm::dvec3(r, 0, r); break;
    case ShapeKind::ring:
    case ShapeKind::cup: lower = glm::dvec3(-r, 0, -r); upper = glm::dvec3(r, shape.height, r); break;
    case ShapeKind::paraboloid:
      lower = glm::dvec3(-r, 0, -r);
      upper = glm::dvec3(r, r * r / (4.0 * shape.focal_length), r);
      break;
    default: lower = glm::dvec3(-1); upper = glm::dvec3(1); break;
  }
  // A little slack so that Embree's float bounds never clip an exact hit.
  glm::dvec3 slack = (upper - lower) * 1e-6 + 1e-6;
  lower -= slack;
  upper += slack;
}

}  // namespace causticbench
