// Geodesic spheres, shared by lpi and csl (csl's dynamic light directions are the same spheres). For
// lpi (Wyman et al. 2003): the light sample directions of Section 4.1 (an
// icosahedron subdivided 3 to 6 times, sampled at its vertices or face centres) and the angular cells
// of the concentric-shell storage of Section 4.2 ("we avoid the difficulty of indexing into a geodesic
// by using a table lookup"), as one spherical triangulation with constant-time point location.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "core/math.h"

namespace causticbench {

// Solid angle of the spherical triangle (a, b, c), unit vectors (Van Oosterom & Strackee 1983).
double solid_angle(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c);

// A triangulation of the unit sphere: unit points and triangles over them, counter-clockwise seen from
// outside. Both factories give the convex hull of the points (every edge convex; for face centres up
// to the float rounding of cocircular quads, where either diagonal would do; tested), so the mesh is
// the spherical Delaunay triangulation and a greedy walk finds the nearest point. Point location goes
// through a cube-map table that lists, per texel of each cube face, every triangle that may overlap
// it, so the containing triangle is always among a texel's candidates (3.4 on average; no walk).
class SphericalMesh {
 public:
  static constexpr int kMaxLevel = 8;
  // A direction within this angle (radians) of a triangle's edge counts as on it: the weight of the
  // opposite corner is then exactly zero. A unit float vector built to lie on an edge (a normalised
  // float midpoint) is off its great circle by rounding, up to 8e-8 (measured in the tests); this is
  // six times that, and far below any triangle's height (1.4e-3 rad at level 8, face centres). The
  // weight of the opposite corner ramps from zero at this distance to its gnomonic value at twice
  // it, so it stays continuous.
  static constexpr double kEdgeTolerance = 1.0 / (1 << 21);

  // The icosahedron subdivided `level` times (0..kMaxLevel, std::invalid_argument otherwise), each
  // triangle into four at its edge midpoints pushed out to the sphere (in double precision): 10 4^level
  // + 2 points, 20 4^level triangles, 30 4^level edges. A level's points are a prefix of the next's.
  static SphericalMesh geodesic_vertices(int level);
  // The normalised centroids of the triangles of geodesic_vertices(level), in its triangle order
  // (20 4^level points); triangles: each dual polygon (the pentagon or hexagon of face centres around
  // one vertex) fan-triangulated, then internal diagonals flipped where that makes the mesh convex
  // (40 4^level - 4 triangles), so that face-centre samples blend barycentrically too.
  static SphericalMesh geodesic_face_centers(int level);

  const std::vector<Vec3>& points() const { return points_; }
  const std::vector<std::array<uint32_t, 3>>& triangles() const { return triangles_; }
  // The points sharing an edge with `point`, ascending.
  std::span<const uint32_t> point_neighbours(uint32_t point) const;

  // The triangle containing unit direction d and the barycentric weights of d's gnomonic (central)
  // projection onto the triangle's plane, in the order of triangles()[triangle]: non-negative, summing
  // to 1, exactly one-hot when d equals a corner bit for bit, exactly zero for the opposite corner when
  // d lies on an edge (within kEdgeTolerance; any adjacent triangle may be returned). The weights are
  // computed in double from the float corners, so they are exact to float rounding for the float d.
  // d must be finite and non-zero; it need not be exactly unit. Cost: one table read, then one triangle
  // tested for 0.63 to 0.69 of random directions on the vertex meshes and 0.57 to 0.64 on the face-centre
  // ones (Geodesic.MostLookupsTestOneTriangle), a few otherwise; its speed, Geodesic.DISABLED_LocateThroughput.
  struct Location {
    uint32_t triangle = 0;
    std::array<float, 3> weights{1.0f, 0.0f, 0.0f};
  };
  Location locate(const Vec3& direction) const;
  // Whether locate(direction) is answered by its texel's likeliest triangle alone (one triangle tested),
  // for measuring the cost quoted above (Geodesic.MostLookupsTestOneTriangle).
  bool located_at_first_candidate(const Vec3& direction) const;
  // The point with the largest dot product with `direction` (ties: any of them).
  uint32_t nearest_point(const Vec3& direction) const;
  // locate's corners (point indices) and weights, sorted by weight descending, for blending.
  struct Corners {
    std::array<uint32_t, 3> points{};
    std::array<float, 3> weights{};
  };
  Corners weighted_corners(const Vec3& direction) const;

  // Per triangle, for edge e (the edge opposite corner e): cross(corner e+1, corner e+2), in double
  // from the float points, rounded; it points into the triangle, and dot(normal, d) is corner e's
  // unnormalised weight. The two triangles on an edge hold the same vector negated, so their side
  // tests are exact opposites and no direction falls between them.
  const std::vector<std::array<Vec3, 3>>& edge_normals() const { return edge_normals_; }
  // Per triangle, for edge e: the triangle on its other side.
  const std::vector<std::array<uint32_t, 3>>& neighbours() const { return neighbours_; }

  // Texels per cube-face side of the lookup table (faces: +x -x +y -y +z -z; on the face of axis k the
  // texel coordinates are d[k+1] / |d[k]| and d[k+2] / |d[k]|, indices mod 3, cut into this many equal
  // parts of [-1, 1]).
  int table_resolution() const { return resolution_; }
  // Candidate triangles per texel, on average: the cost of a lookup.
  double mean_candidates() const;
  // Everything this object holds: points, triangles, edge normals, neighbours, lookup table, point
  // adjacency.
  size_t memory_bytes() const;

  // The lookup table as locate reads it, for a GPU kernel that repeats locate (methods/lpi/lpi.comp):
  // per texel (6 table_resolution()^2, then one more) its likeliest triangle and where its other
  // candidates start in table_candidates(); and the longest edge normal's length, which scales the
  // edge ramp.
  struct Texel {
    uint32_t first;
    uint32_t rest;
  };
  const std::vector<Texel>& table_texels() const { return texels_; }
  const std::vector<uint32_t>& table_candidates() const { return candidates_; }
  double longest_edge() const { return longest_edge_; }

 private:
  // What locate reads of a triangle, in one place so that a lookup touches few cache lines: its
  // corners' coordinates and indices.
  struct TriangleRecord {
    float corner[3][3];
    uint32_t point[3];
  };
  SphericalMesh(const std::vector<glm::dvec3>& points, std::vector<std::array<uint32_t, 3>> triangles);
  void build_edges();
  void build_table();
  uint32_t texel_of(const Vec3& direction) const;
  // A direction's side tests against one triangle: per edge, cross(corner e+1, corner e+2) and its
  // dot product with the direction.
  struct Sides {
    glm::dvec3 normal[3];
    double side[3];
  };
  bool inside(uint32_t triangle, const glm::dvec3& direction, Sides& sides) const;
  Location location_from(uint32_t triangle, const Sides& sides) const;

  std::vector<Vec3> points_;
  std::vector<std::array<uint32_t, 3>> triangles_;
  std::vector<std::array<Vec3, 3>> edge_normals_;
  std::vector<std::array<uint32_t, 3>> neighbours_;
  std::vector<uint32_t> point_neighbour_begin_;  // points + 1 offsets into point_neighbours_
  std::vector<uint32_t> point_neighbours_;
  std::vector<TriangleRecord> records_;
  double longest_edge_ = 0.0;  // the largest |cross(corner e+1, corner e+2)|, a little over
  int resolution_ = 1;
  std::vector<Texel> texels_;         // 6 resolution^2, then one whose rest ends the last texel's
  std::vector<uint32_t> candidates_;  // per texel after its first, the likelier first
};

}  // namespace causticbench
