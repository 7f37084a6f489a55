// The built-in shapes, in object space. Curved shapes whose normals shape the caustic (sphere, disk,
// ring, cup, paraboloid dish) are intersected exactly, with exact normals, as Embree user geometry.
// Flat-faced shapes (quad, box, prism) are exact as triangles. The torus, the water height field and
// imported meshes are triangle meshes with interpolated normals: the torus and the water surface get
// analytic normals at their vertices (see docs/scene-format.md for the tessellation error bound).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include "core/config.h"
#include "core/math.h"

namespace causticbench {

enum class ShapeKind { quad, disk, sphere, ring, cup, torus, box, prism, paraboloid, water, mesh };

struct TriangleMesh {
  std::vector<Vec3> positions;
  std::vector<Vec3> normals;  // per vertex, used when smooth
  std::vector<glm::uvec3> triangles;
  bool smooth = false;
  // Flips triangles whose winding disagrees with their vertex normals, so that the winding normal
  // always points to the outside (the side the vertex normals face).
  void orient_by_normals();
  void compute_flat_normals();
};

// One sinusoidal wave of the water surface: height += amplitude * sin(k (x cos a + z sin a) + phase),
// with k = 2 pi / wavelength and phase = phase_degrees + frame * phase_per_frame_degrees.
struct WaterWave {
  double amplitude = 0.02;
  double wavelength = 0.5;
  double direction_degrees = 0.0;
  double phase_degrees = 0.0;
  double phase_per_frame_degrees = 0.0;
};

struct ShapeDesc {
  ShapeKind kind = ShapeKind::sphere;
  double radius = 1.0;         // disk, sphere, ring, cup, paraboloid (aperture)
  double height = 1.0;         // ring, cup
  double thickness = 0.0;      // ring: 0 is an infinitely thin band; > 0 a solid ring with that wall
  double major_radius = 1.0;   // torus
  double minor_radius = 0.25;  // torus
  double focal_length = 1.0;   // paraboloid: y = (x^2 + z^2) / (4 f)
  double side = 1.0;           // prism: side of the equilateral cross-section
  double length = 1.0;         // prism: extent along z
  glm::dvec2 size{1.0, 1.0};   // quad, water: extent along x and z
  glm::dvec3 box_size{1.0, 1.0, 1.0};
  glm::ivec2 segments{256, 64};   // torus: around the major and the minor circle
  glm::ivec2 resolution{128, 128};  // water: grid cells along x and z
  std::vector<WaterWave> waves;
  std::string asset;           // mesh: the asset name as written
  std::shared_ptr<const TriangleMesh> mesh;  // mesh: loaded at scene load

  bool is_analytic() const;
  bool changes_with_frame() const;  // water with moving waves
};

// Reads a shape map; `scene_folder` anchors mesh asset lookup.
ShapeDesc read_shape(const ConfigNode& node, const std::string& scene_folder);
std::string shape_kind_name(ShapeKind kind);
const std::vector<std::string>& shape_kind_names();

// Triangle meshes of the non-analytic shapes, in object space, for the given frame.
TriangleMesh tessellate(const ShapeDesc& shape, double frame);

// Exact intersection of the analytic shapes, in object space and double precision. `surface` names
// which part was hit (e.g. a cup's wall or bottom), for the normal.
struct AnalyticHit {
  double t = 0.0;
  int surface = 0;
};
bool intersect_analytic(const ShapeDesc& shape, const glm::dvec3& origin, const glm::dvec3& direction, double t_min,
                        double t_max, AnalyticHit& hit);
// Every analytic surface's outward normal, unnormalised, is affine in the object-space point: g(p) =
// gradient p + offset (a sphere's p, a ring wall's radial (x, 0, z), a paraboloid's (-2x, 4f, -2z), a flat
// face's constant). So the unit normal's change along a step s is (I - n n^T) gradient s / |g|, exactly:
// what ray differentials need (Tracer::shading_normal_change), with no finite difference.
struct AffineNormal {
  glm::dmat3 gradient{0.0};
  glm::dvec3 offset{0.0};
};
AffineNormal analytic_normal_field(const ShapeDesc& shape, int surface);
// Outward unit normal of an analytic shape at an object-space point on the given surface: its affine
// field's direction there.
glm::dvec3 analytic_normal(const ShapeDesc& shape, int surface, const glm::dvec3& point);
void analytic_bounds(const ShapeDesc& shape, glm::dvec3& lower, glm::dvec3& upper);

// Water height and its gradient, shared by the tessellation and tests.
double water_height(const ShapeDesc& shape, double x, double z, double frame, double* dh_dx, double* dh_dz);

}  // namespace causticbench
