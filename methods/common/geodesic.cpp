#include "methods/common/geodesic.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

namespace causticbench {

namespace {

using Triangle = std::array<uint32_t, 3>;
using glm::dvec3;

void check_level(int level) {
  if (level < 0 || level > SphericalMesh::kMaxLevel) {
    throw std::invalid_argument("geodesic sphere: level " + std::to_string(level) + " is not in 0 .. " +
                                std::to_string(SphericalMesh::kMaxLevel));
  }
}

// Counter-clockwise seen from outside: the corners' triple product is positive.
void orient(const std::vector<dvec3>& points, Triangle& t) {
  if (glm::dot(points[t[0]], glm::cross(points[t[1]], points[t[2]])) < 0.0) std::swap(t[1], t[2]);
}

// The triangles around each point, in compressed rows, to find the one holding a directed edge.
struct Incidence {
  Incidence(size_t point_count, const std::vector<Triangle>& triangles) : triangles(triangles) {
    begin.assign(point_count + 1, 0);
    for (const Triangle& t : triangles) {
      for (uint32_t p : t) ++begin[p + 1];
    }
    for (size_t p = 0; p < point_count; ++p) begin[p + 1] += begin[p];
    list.resize(3 * triangles.size());
    std::vector<uint32_t> cursor(begin.begin(), begin.end() - 1);
    for (uint32_t t = 0; t < triangles.size(); ++t) {
      for (uint32_t p : triangles[t]) list[cursor[p]++] = t;
    }
  }
  // The triangle holding the directed edge from -> to, and the corner where `from` sits in it.
  std::pair<uint32_t, int> with_edge(uint32_t from, uint32_t to) const {
    for (uint32_t k = begin[from]; k < begin[from + 1]; ++k) {
      const Triangle& t = triangles[list[k]];
      const int at = t[0] == from ? 0 : (t[1] == from ? 1 : 2);
      if (t[(at + 1) % 3] == to) return {list[k], at};
    }
    throw std::logic_error("SphericalMesh: the triangles do not close up");
  }
  const std::vector<Triangle>& triangles;
  std::vector<uint32_t> begin, list;
};

void geodesic(int level, std::vector<dvec3>& points, std::vector<Triangle>& triangles) {
  check_level(level);
  const double phi = (1.0 + std::sqrt(5.0)) / 2.0;
  points = {{-1, phi, 0}, {1, phi, 0}, {-1, -phi, 0}, {1, -phi, 0}, {0, -1, phi}, {0, 1, phi},
            {0, -1, -phi}, {0, 1, -phi}, {phi, 0, -1}, {phi, 0, 1}, {-phi, 0, -1}, {-phi, 0, 1}};
  for (dvec3& p : points) p = glm::normalize(p);
  triangles = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
               {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
               {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
  for (Triangle& t : triangles) orient(points, t);
  for (int l = 0; l < level; ++l) {
    // The midpoint of edge e (corner e to corner e+1) of each triangle, made once per edge.
    const Incidence around(points.size(), triangles);
    std::vector<uint32_t> midpoints(3 * triangles.size(), UINT32_MAX);
    for (uint32_t t = 0; t < triangles.size(); ++t) {
      for (int e = 0; e < 3; ++e) {
        if (midpoints[3 * t + e] != UINT32_MAX) continue;
        const uint32_t a = triangles[t][e], b = triangles[t][(e + 1) % 3];
        midpoints[3 * t + e] = static_cast<uint32_t>(points.size());
        points.push_back(glm::normalize(points[a] + points[b]));
        const auto [other, at] = around.with_edge(b, a);
        midpoints[3 * other + at] = midpoints[3 * t + e];
      }
    }
    auto midpoint = [&](uint32_t t, int e) { return midpoints[3 * t + e]; };
    std::vector<Triangle> finer;
    finer.reserve(triangles.size() * 4);
    for (uint32_t index = 0; index < triangles.size(); ++index) {
      const Triangle& t = triangles[index];
      const uint32_t ab = midpoint(index, 0), bc = midpoint(index, 1), ca = midpoint(index, 2);
      finer.push_back({t[0], ab, ca});
      finer.push_back({ab, t[1], bc});
      finer.push_back({ca, bc, t[2]});
      finer.push_back({ab, bc, ca});
    }
    triangles = std::move(finer);
  }
}

}  // namespace

SphericalMesh SphericalMesh::geodesic_vertices(int level) {
  std::vector<dvec3> points;
  std::vector<Triangle> triangles;
  geodesic(level, points, triangles);
  return SphericalMesh(points, std::move(triangles));
}

SphericalMesh SphericalMesh::geodesic_face_centers(int level) {
  std::vector<dvec3> vertices;
  std::vector<Triangle> faces;
  geodesic(level, vertices, faces);
  std::vector<dvec3> centers;
  centers.reserve(faces.size());
  for (const Triangle& t : faces) centers.push_back(glm::normalize(vertices[t[0]] + vertices[t[1]] + vertices[t[2]]));
  const Incidence around(vertices.size(), faces);
  std::vector<Triangle> triangles, polygon;
  triangles.reserve(2 * faces.size());
  std::vector<uint32_t> ring;
  for (uint32_t v = 0; v < vertices.size(); ++v) {
    // Around vertex v, face (v, a, b) is followed counter-clockwise by the face holding edge v -> b.
    ring.clear();
    const uint32_t first = around.list[around.begin[v]];
    uint32_t face = first;
    do {
      ring.push_back(face);
      const Triangle& t = faces[face];
      const int at = t[0] == v ? 0 : (t[1] == v ? 1 : 2);
      face = around.with_edge(v, t[(at + 2) % 3]).first;
    } while (face != first && ring.size() < 7);
    polygon.clear();
    for (size_t i = 1; i + 1 < ring.size(); ++i) polygon.push_back({ring[0], ring[i], ring[i + 1]});
    for (Triangle& t : polygon) orient(centers, t);
    // A fan need not be convex (a hexagon's points are not coplanar): flip each diagonal whose far
    // point lies outside the plane of the triangle across it, until none does (Lawson's flips, which
    // end at the convex hull). Only the polygon's own diagonals flip, so its triangles stay within it;
    // the tests check that the polygons' sides come out convex as well.
    // (Each flip strictly lowers the surface, so this ends; the bound is a guard against rounding.)
    int rounds = 0;
    for (bool flipped = true; flipped && rounds < 64; ++rounds) {
      flipped = false;
      for (size_t i = 0; i < polygon.size() && !flipped; ++i) {
        for (size_t j = 0; j < polygon.size() && !flipped; ++j) {
          for (int e = 0; e < 3 && i != j && !flipped; ++e) {
            const uint32_t a = polygon[i][e], b = polygon[i][(e + 1) % 3], c = polygon[i][(e + 2) % 3];
            const Triangle& o = polygon[j];
            const int f = o[0] == b ? 0 : (o[1] == b ? 1 : (o[2] == b ? 2 : -1));
            if (f < 0 || o[(f + 1) % 3] != a) continue;
            const uint32_t s = o[(f + 2) % 3];
            const dvec3 outward = glm::cross(centers[b] - centers[a], centers[c] - centers[a]);
            if (!(glm::dot(outward, centers[s] - centers[a]) > 1e-15 * glm::length(outward))) continue;
            polygon[i] = {a, s, c};
            polygon[j] = {s, b, c};
            flipped = true;
          }
        }
      }
    }
    triangles.insert(triangles.end(), polygon.begin(), polygon.end());
  }
  return SphericalMesh(centers, std::move(triangles));
}

SphericalMesh::SphericalMesh(const std::vector<dvec3>& points, std::vector<Triangle> triangles)
    : triangles_(std::move(triangles)) {
  points_.reserve(points.size());
  for (const dvec3& p : points) points_.push_back(Vec3(p));
  build_edges();
  build_table();
}

void SphericalMesh::build_edges() {
  edge_normals_.resize(triangles_.size());
  neighbours_.assign(triangles_.size(), {0, 0, 0});
  const Incidence around(points_.size(), triangles_);
  for (uint32_t t = 0; t < triangles_.size(); ++t) {
    for (int e = 0; e < 3; ++e) {
      // In double, cross(a, b) of float vectors is exactly -cross(b, a) (see inside()), and so is
      // its rounding to float: the triangle across holds exactly the opposite normal.
      const uint32_t from = triangles_[t][(e + 1) % 3], to = triangles_[t][(e + 2) % 3];
      edge_normals_[t][e] = Vec3(glm::cross(dvec3(points_[from]), dvec3(points_[to])));
      neighbours_[t][e] = around.with_edge(to, from).first;
    }
  }
  longest_edge_ = 0.0;
  for (const auto& normals : edge_normals_) {
    for (const Vec3& n : normals) longest_edge_ = std::max(longest_edge_, 1.001 * glm::length(dvec3(n)));
  }
  records_.resize(triangles_.size());
  for (size_t t = 0; t < triangles_.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const Vec3& p = points_[triangles_[t][k]];
      records_[t].corner[k][0] = p.x, records_[t].corner[k][1] = p.y, records_[t].corner[k][2] = p.z;
      records_[t].point[k] = triangles_[t][k];
    }
  }
  // A point's neighbours: the corner after it in each triangle around it (each edge once per side).
  point_neighbour_begin_.assign(around.begin.begin(), around.begin.end());
  point_neighbours_.resize(around.list.size());
  for (uint32_t p = 0; p < points_.size(); ++p) {
    for (uint32_t k = around.begin[p]; k < around.begin[p + 1]; ++k) {
      const Triangle& t = triangles_[around.list[k]];
      const int at = t[0] == p ? 0 : (t[1] == p ? 1 : 2);
      point_neighbours_[k] = t[(at + 1) % 3];
    }
    std::sort(point_neighbours_.begin() + around.begin[p], point_neighbours_.begin() + around.begin[p + 1]);
  }
  point_neighbours_.shrink_to_fit();
}

std::span<const uint32_t> SphericalMesh::point_neighbours(uint32_t point) const {
  return {point_neighbours_.data() + point_neighbour_begin_[point],
          point_neighbour_begin_[point + 1] - point_neighbour_begin_[point]};
}

// The table: for every texel, every triangle not separated from it by one of the texel's four planes
// or one of the triangle's three, so always a superset of the triangles overlapping it. Texels grow
// by a margin far above the rounding of texel_of, so a direction always finds its triangle.
void SphericalMesh::build_table() {
  // About 2.25 texels per triangle: 3.4 candidates per texel (mean_candidates), a small table.
  resolution_ = std::max(1, static_cast<int>(std::ceil(1.5 * std::sqrt(triangles_.size() / 6.0))));
  const int n = resolution_;
  const double margin = 1.0 / 65536.0;
  auto texel_index = [n](double u) { return std::clamp(static_cast<int>(std::floor((u + 1.0) * 0.5 * n)), 0, n - 1); };
  struct Entry {
    uint32_t texel;
    float priority;
    uint32_t triangle;
  };
  std::vector<Entry> entries;
  entries.reserve(6 * triangles_.size());
  for (uint32_t t = 0; t < triangles_.size(); ++t) {
    const dvec3 c[3] = {dvec3(points_[triangles_[t][0]]), dvec3(points_[triangles_[t][1]]), dvec3(points_[triangles_[t][2]])};
    dvec3 unit_normal[3];
    for (int e = 0; e < 3; ++e) unit_normal[e] = glm::normalize(dvec3(edge_normals_[t][e]));
    const dvec3 centroid = glm::normalize(c[0] + c[1] + c[2]);
    // A triangle with a corner outside a face's hemisphere reaches that face's region (within 54.7
    // degrees of its axis) only if it spans more than 35 degrees: only levels 0 and 1 have such
    // triangles, and those few are tested against the whole face.
    const double narrowest = std::min({glm::dot(c[0], c[1]), glm::dot(c[1], c[2]), glm::dot(c[2], c[0])});
    const bool small = narrowest > std::sqrt(3.0) / 2.0;  // cos 30 degrees
    for (int face = 0; face < 6; ++face) {
      const int axis = face / 2, a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
      const double sign = face % 2 ? -1.0 : 1.0;
      const double height[3] = {sign * c[0][axis], sign * c[1][axis], sign * c[2][axis]};
      int i0 = 0, i1 = n - 1, j0 = 0, j1 = n - 1;
      if (std::min({height[0], height[1], height[2]}) > 1e-6) {
        // In the face's hemisphere the central projection maps the triangle onto the planar triangle
        // of its projected corners: their bounding box bounds it.
        double u_low = 2.0, u_high = -2.0, v_low = 2.0, v_high = -2.0;
        for (int k = 0; k < 3; ++k) {
          const double u = c[k][a1] / height[k], v = c[k][a2] / height[k];
          u_low = std::min(u_low, u), u_high = std::max(u_high, u);
          v_low = std::min(v_low, v), v_high = std::max(v_high, v);
        }
        if (u_low > 1.0 + margin || u_high < -1.0 - margin || v_low > 1.0 + margin || v_high < -1.0 - margin) continue;
        i0 = texel_index(u_low - 2 * margin), i1 = texel_index(u_high + 2 * margin);
        j0 = texel_index(v_low - 2 * margin), j1 = texel_index(v_high + 2 * margin);
      } else if (small) {
        continue;
      }
      for (int j = j0; j <= j1; ++j) {
        const double v0 = -1.0 + 2.0 * j / n - margin, v1 = -1.0 + 2.0 * (j + 1) / n + margin;
        for (int i = i0; i <= i1; ++i) {
          const double u0 = -1.0 + 2.0 * i / n - margin, u1 = -1.0 + 2.0 * (i + 1) / n + margin;
          // The texel's planes: u0 <= d[a1] / (sign d[axis]) <= u1, the same for v.
          auto all_corners = [&](auto&& outside) { return outside(c[0], height[0]) && outside(c[1], height[1]) && outside(c[2], height[2]); };
          if (all_corners([&](const dvec3& p, double h) { return p[a1] < u0 * h; }) ||
              all_corners([&](const dvec3& p, double h) { return p[a1] > u1 * h; }) ||
              all_corners([&](const dvec3& p, double h) { return p[a2] < v0 * h; }) ||
              all_corners([&](const dvec3& p, double h) { return p[a2] > v1 * h; })) {
            continue;
          }
          // The triangle's planes, against the texel's four corner rays: beyond twice the edge
          // tolerance, the texel's whole cone is, and locate would refuse the triangle there anyway.
          // (The rays are not normalised: at most sqrt(3) long, they are held to sqrt(3) times that.)
          dvec3 rays[4];
          for (int k = 0; k < 4; ++k) {
            rays[k][axis] = sign;
            rays[k][a1] = k & 1 ? u1 : u0;
            rays[k][a2] = k & 2 ? v1 : v0;
          }
          bool separated = false;
          for (int e = 0; e < 3 && !separated; ++e) {
            separated = true;
            for (const dvec3& ray : rays) separated = separated && glm::dot(unit_normal[e], ray) < -2.0 * std::sqrt(3.0) * kEdgeTolerance;
          }
          if (separated) continue;
          dvec3 center;
          center[axis] = sign;
          center[a1] = 0.5 * (u0 + u1);
          center[a2] = 0.5 * (v0 + v1);
          const uint32_t texel = static_cast<uint32_t>((face * n + j) * n + i);
          entries.push_back({texel, static_cast<float>(glm::dot(glm::normalize(center), centroid)), t});
        }
      }
    }
  }
  // The likeliest triangle (the one whose centroid is nearest the texel's centre) first.
  std::sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) {
    return a.texel != b.texel ? a.texel < b.texel : (a.priority != b.priority ? a.priority > b.priority : a.triangle < b.triangle);
  });
  const size_t texel_count = 6 * static_cast<size_t>(n) * n;
  texels_.assign(texel_count + 1, Texel{0, 0});
  candidates_.clear();
  candidates_.reserve(entries.size() - texel_count);
  size_t k = 0;
  for (size_t texel = 0; texel < texel_count; ++texel) {
    if (k == entries.size() || entries[k].texel != texel) throw std::logic_error("SphericalMesh: a lookup texel has no triangle");
    texels_[texel].first = entries[k++].triangle;
    texels_[texel].rest = static_cast<uint32_t>(candidates_.size());
    for (; k < entries.size() && entries[k].texel == texel; ++k) candidates_.push_back(entries[k].triangle);
  }
  texels_[texel_count].rest = static_cast<uint32_t>(candidates_.size());
}

[[gnu::always_inline]] inline uint32_t SphericalMesh::texel_of(const Vec3& d) const {
  // Selections rather than branches: for scattered directions the major axis is unpredictable.
  const float ax = std::fabs(d.x), ay = std::fabs(d.y), az = std::fabs(d.z);
  const bool x_major = (ax >= ay) & (ax >= az), y_major = !x_major & (ay >= az);
  const int axis = x_major ? 0 : (y_major ? 1 : 2);
  const float major = x_major ? d.x : (y_major ? d.y : d.z);
  const float u = x_major ? d.y : (y_major ? d.z : d.x);
  const float v = x_major ? d.z : (y_major ? d.x : d.y);
  const int n = resolution_;
  const float scale = 0.5f * n / std::fabs(major);
  // Written so that NaN (a zero or non-finite direction) lands in texel 0 rather than out of range.
  const float fu = (u + std::fabs(major)) * scale, fv = (v + std::fabs(major)) * scale;
  const int i = fu > 0.0f ? std::min(static_cast<int>(fu), n - 1) : 0;
  const int j = fv > 0.0f ? std::min(static_cast<int>(fv), n - 1) : 0;
  const int face = 2 * axis + (major < 0.0f ? 1 : 0);
  return static_cast<uint32_t>((face * n + j) * n + i);
}

// The side tests from the corners in double: products of floats are exact there, so each component of
// cross(a, b) is one rounding of an exact difference and cross(b, a) is its exact negation. The two
// triangles on an edge therefore see exactly opposite sides, and no direction falls between them.
[[gnu::always_inline]] inline bool SphericalMesh::inside(uint32_t triangle, const glm::dvec3& d, Sides& sides) const {
  const float* c = records_[triangle].corner[0];
  const double ax = c[0], ay = c[1], az = c[2], bx = c[3], by = c[4], bz = c[5], cx = c[6], cy = c[7], cz = c[8];
  // Edge e's normal is cross(corner e+1, corner e+2): b x c, c x a, a x b.
  sides.normal[0] = {by * cz - bz * cy, bz * cx - bx * cz, bx * cy - by * cx};
  sides.normal[1] = {cy * az - cz * ay, cz * ax - cx * az, cx * ay - cy * ax};
  sides.normal[2] = {ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx};
  bool within = true;
  for (int e = 0; e < 3; ++e) {
    const dvec3& n = sides.normal[e];
    const double side = d.x * n.x + d.y * n.y + d.z * n.z;
    sides.side[e] = side;
    // Outside the edge by more than the tolerance (side / |n| is the sine of the distance).
    if (side < 0.0 && side * side > kEdgeTolerance * kEdgeTolerance * glm::dot(n, n)) within = false;
  }
  return within;
}

// The weights are the sides themselves (the triple products det(d, b, c) etc., in double from the
// corners, so as exact as the float direction and points allow), ramped near the edges.
[[gnu::always_inline]] inline SphericalMesh::Location SphericalMesh::location_from(uint32_t triangle, const Sides& sides) const {
  // The distance ramp: zero within kEdgeTolerance of the edge, the gnomonic weight beyond twice it
  // (the edge's length only near it: no edge is longer than the mesh's longest).
  auto ramp = [&](int e) {
    const double side = sides.side[e];
    if (side >= 2.0 * kEdgeTolerance * longest_edge_) return side;
    const double band = 2.0 * kEdgeTolerance * std::sqrt(glm::dot(sides.normal[e], sides.normal[e]));
    return side >= band ? side : (side > 0.5 * band ? 2.0 * (side - 0.5 * band) : 0.0);
  };
  const double r0 = ramp(0), r1 = ramp(1), r2 = ramp(2), total = r0 + r1 + r2;
  if (!(total > 0.0)) {
    // A degenerate direction: the corner it is nearest in the side tests.
    const double* s = sides.side;
    const int corner = s[0] >= s[1] ? (s[0] >= s[2] ? 0 : 2) : (s[1] >= s[2] ? 1 : 2);
    return Location{triangle, {corner == 0 ? 1.0f : 0.0f, corner == 1 ? 1.0f : 0.0f, corner == 2 ? 1.0f : 0.0f}};
  }
  const double scale = 1.0 / total;
  float w0 = static_cast<float>(r0 * scale), w1 = static_cast<float>(r1 * scale), w2 = static_cast<float>(r2 * scale);
  // The largest weight takes what rounding left, so the three sum to 1 in float (and a corner's
  // weight is exactly 1 when the others are 0).
  if (w0 >= w1 && w0 >= w2) {
    w0 = 1.0f - (w1 + w2);
  } else if (w1 >= w2) {
    w1 = 1.0f - (w2 + w0);
  } else {
    w2 = 1.0f - (w0 + w1);
  }
  return Location{triangle, {w0, w1, w2}};
}

SphericalMesh::Location SphericalMesh::locate(const Vec3& direction) const {
  const uint32_t index = texel_of(direction);
  const dvec3 d(direction);
  Sides sides;
  const Texel& texel = texels_[index];
  if (inside(texel.first, d, sides)) return location_from(texel.first, sides);
  uint32_t best = texel.first;
  Sides best_sides = sides;
  for (uint32_t k = texel.rest; k < texels_[index + 1].rest; ++k) {
    const uint32_t triangle = candidates_[k];
    if (inside(triangle, d, sides)) return location_from(triangle, sides);
    // Only a degenerate direction gets past every candidate: it keeps the least-outside one.
    if (std::min({sides.side[0], sides.side[1], sides.side[2]}) >
        std::min({best_sides.side[0], best_sides.side[1], best_sides.side[2]})) {
      best = triangle, best_sides = sides;
    }
  }
  return location_from(best, best_sides);
}

bool SphericalMesh::located_at_first_candidate(const Vec3& direction) const {
  Sides sides;
  return inside(texels_[texel_of(direction)].first, dvec3(direction), sides);
}

uint32_t SphericalMesh::nearest_point(const Vec3& direction) const {
  const glm::dvec3 d(direction);
  const uint32_t* corners = records_[locate(direction).triangle].point;
  uint32_t best = corners[0];
  double best_dot = glm::dot(glm::dvec3(points_[best]), d);
  for (int k = 1; k < 3; ++k) {
    const double dot = glm::dot(glm::dvec3(points_[corners[k]]), d);
    if (dot > best_dot) best_dot = dot, best = corners[k];
  }
  // Greedy walk over the Delaunay graph: a point that is not the nearest has a nearer neighbour.
  for (bool moved = true; moved;) {
    moved = false;
    for (uint32_t neighbour : point_neighbours(best)) {
      const double dot = glm::dot(glm::dvec3(points_[neighbour]), d);
      if (dot > best_dot) best_dot = dot, best = neighbour, moved = true;
    }
  }
  return best;
}

SphericalMesh::Corners SphericalMesh::weighted_corners(const Vec3& direction) const {
  const Location location = locate(direction);
  std::array<int, 3> order{0, 1, 2};
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return location.weights[a] > location.weights[b]; });
  Corners corners;
  for (int k = 0; k < 3; ++k) {
    corners.points[k] = triangles_[location.triangle][order[k]];
    corners.weights[k] = location.weights[order[k]];
  }
  return corners;
}

double SphericalMesh::mean_candidates() const {
  return static_cast<double>(candidates_.size()) / static_cast<double>(texels_.size() - 1) + 1.0;
}

size_t SphericalMesh::memory_bytes() const {
  return sizeof(*this) + points_.capacity() * sizeof(Vec3) + triangles_.capacity() * sizeof(Triangle) +
         edge_normals_.capacity() * sizeof(edge_normals_[0]) + neighbours_.capacity() * sizeof(Triangle) +
         records_.capacity() * sizeof(TriangleRecord) + texels_.capacity() * sizeof(Texel) +
         (point_neighbour_begin_.capacity() + point_neighbours_.capacity() + candidates_.capacity()) * sizeof(uint32_t);
}

double solid_angle(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  const double numerator = std::fabs(glm::dot(a, glm::cross(b, c)));
  const double denominator = 1.0 + glm::dot(a, b) + glm::dot(b, c) + glm::dot(c, a);
  return 2.0 * std::atan2(numerator, denominator);
}

}  // namespace causticbench
