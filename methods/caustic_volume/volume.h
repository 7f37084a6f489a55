// Caustic volumes (Ernst, Akenine-Möller & Jensen 2005): the warped volume of one lit specular triangle,
// bounded by its three vertex rays, and what a receiver point inside it receives. Built per light and
// object every frame (beams.cpp); tested against receiver points (containment.cpp).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "core/light.h"
#include "core/material.h"
#include "core/math.h"
#include "core/shape.h"
#include "core/tracer.h"
#include "methods/common/analytic_mesh.h"

namespace causticbench::caustic_volume {

enum class Intensity { constant, interpolated };
// Glass: one interface (the receivers lie in the medium: a water surface), through the object to where
// each ray leaves it (a solid), or auto: through where the refracted ray meets its object again.
enum class Refraction { automatic, one_interface, through_object };

// One caustic volume: X(b, t) = sum_i b_i (P_i + t D_i), b in the triangle, 0 <= t <= t_max.
struct Volume {
  std::array<glm::dvec3, 3> origin;     // P_i, on the specular surface
  std::array<glm::dvec3, 3> direction;  // D_i, unit: reflected or refracted at the vertex's shading normal
  double t_max = 0.0;                   // the far cap
  // The light arriving, per vertex: irradiance across the incoming light times the reflectance or the
  // Fresnel transmittance there (W/m^2 across the light, after the interface).
  std::array<Color, 3> arriving{Color(0.0f), Color(0.0f), Color(0.0f)};
  // intensity: constant. The triangle's area across the incoming light at its centroid, and the mean
  // outgoing direction across which the cross-sections are measured.
  double area_in = 0.0;
  glm::dvec3 mean_direction{0.0};
  // intensity: interpolated. Per vertex the wavefront around it: the area of its lit one-ring across
  // the light arriving there, and the one-ring's cross-section across D_i as it travels, a quadratic
  // in t (coefficients of 1, t, t^2; signed, its magnitude is the area).
  std::array<double, 3> ring_area_in{0.0, 0.0, 0.0};
  std::array<std::array<double, 3>, 3> ring_area_out{};
  Color absorption{0.0f};  // of the medium the rays travel in (one refracting interface), per scene unit
  int object = -1;
  int side = 1;  // the side of the surface the light arrives on: +1 the side its normals face, -1 the other
  // A receiver point of the volume's own object (a diffuse mirror receives caustics) gets its light only
  // beyond this distance along the rays: half the triangle's longest edge, more than the sagitta by which
  // the exact surface departs from the flat triangle, so that a surface does not light itself.
  double self_gap = 0.0;
  // The cubic's vector coefficients (containment.cpp): cross(E1(t), E2(t)) = k[0] + k[1] t + k[2] t^2 with
  // E_j(t) = (P_j - P_0) + t (D_j - D_0), and their products with D_0.
  std::array<glm::dvec3, 3> k{};
  std::array<double, 3> k_dot_d0{0.0, 0.0, 0.0};
  glm::dvec3 lower{0.0}, upper{0.0};  // the bounds of its six corners, which hold it (a convex hull does)
  double flux = 0.0;                   // luminance of the flux leaving the surface into the volume, W
  double flux_entering = 0.0;          // luminance of the flux entering the triangle, W (before the
                                       // reflectance or transmittance: the lost-flux counter's unit)
};

// What became of one object's triangles under one light.
struct BeamStatistics {
  uint64_t triangles = 0;  // of the object's mesh
  uint64_t lit = 0;        // volumes built
  uint64_t unlit = 0;      // facing away, or shadowed at their centroid
  uint64_t dropped = 0;    // a vertex ray could not leave (refraction impossible, trapped inside a solid)
  uint64_t torn = 0;       // through a solid: its rays left with different internal reflections
  double flux_lit = 0.0;      // luminance of the flux entering the volumes built, W
  double flux_dropped = 0.0;  // entering the dropped ones
  double flux_torn = 0.0;     // entering the torn ones
  void add(const BeamStatistics& other);
};

// The box that holds every receiver of the frame (their exact bounds: meshes' vertices, analytic shapes'
// boxes), and the far cap it gives a volume: where every ray of the volume has left it. Per axis, when the
// three vertex rays travel the same way along it, every ray between them leaves that slab by the largest
// of the three's exits (the exit distance is a ratio of functions linear in b, extreme at the vertices);
// the box is left by the smallest of the slabs' bounds. Infinite when no slab bounds it.
struct ReceiverBox {
  glm::dvec3 lower{0.0}, upper{0.0};
  bool empty = true;
};
ReceiverBox receiver_box(const SceneFrame& frame);
double box_cap(const ReceiverBox& box, const std::array<glm::dvec3, 3>& origin, const std::array<glm::dvec3, 3>& direction);

// Every volume of `mesh` (object `object`) under `light`: the triangles the light reaches (facing it,
// with a vertex that sees the light; a shadowed vertex brings none), their vertex rays reflected
// (mirrors) or refracted (glass, by `refraction`: once into the medium, or through the solid to where
// each ray leaves it, its total internal reflections followed), the intensities of both modes. Through
// a solid the volume starts where its rays leave; its densities still count the area the light entered.
// The far cap: `t_max`, or with `box` the smaller of t_max and the box's cap. Appends to `volumes`.
void build_volumes(const Tracer& tracer, const LightFrame& light, const SurfaceMesh& mesh, int object,
                   const Material& material, Refraction refraction, double t_max, const ReceiverBox* box,
                   std::vector<Volume>& volumes, BeamStatistics& statistics);

// Fills the cubic's coefficients and the bounds (after build_volumes sets the rays).
void finish_volume(Volume& volume);

// Every real root of c0 + c1 t + c2 t^2 + c3 t^3 in [0, t_max], ascending; returns how many (at most 3).
// Robust where the cubic degenerates (nearly parallel vertex rays: nearly quadratic or linear): it brackets
// the roots between the critical points and refines each bracket, never dividing by a leading coefficient.
int cubic_roots(double c0, double c1, double c2, double c3, double t_max, double roots[3]);

// Where the volume passes through x: a root t of the cubic with x inside the cross-section T(t), and x's
// barycentric weights there. More than one near a fold, where several sheets of the beam cross.
struct Sheet {
  double t = 0.0;
  std::array<double, 3> weights{0.0, 0.0, 0.0};
};
// The sheets through x (at most 3), by t; returns how many.
int sheets_through(const Volume& volume, const glm::dvec3& x, Sheet sheets[3], double t_min = 0.0);

// The irradiance across the beam on one sheet (W/m^2 across its interpolated direction), before the
// receiver's cosine and the medium's absorption.
Color beam_irradiance(const Volume& volume, const Sheet& sheet, Intensity intensity);

// What one sheet gives the receiver point x of unit normal n: the beam's irradiance times |n . D(w)| times
// the medium's transmittance from where the light left the surface.
Color sheet_irradiance(const Volume& volume, const Sheet& sheet, const glm::dvec3& x, const glm::dvec3& n,
                       Intensity intensity);

// E_c that `volume` gives a receiver point x of unit normal n: every sheet through x beyond t_min adds its
// light.
Color volume_irradiance(const Volume& volume, const glm::dvec3& x, const glm::dvec3& n, Intensity intensity,
                        double t_min = 0.0);

}  // namespace causticbench::caustic_volume
