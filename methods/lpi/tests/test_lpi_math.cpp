// lpi's two math modules: the geodesic sphere with its point location (methods/common/geodesic.h) and
// real spherical harmonics (methods/common/spherical_harmonics.h). Links only causticbench_core.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <map>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>

#include "core/sampling.h"
#include "methods/common/geodesic.h"
#include "methods/common/spherical_harmonics.h"

namespace causticbench::lpi {
namespace {

using glm::dvec3;

dvec3 random_direction(Random& random) {
  const double z = 1.0 - 2.0 * random.uniform_double(), phi = 2.0 * kPiDouble * random.uniform_double();
  const double s = std::sqrt(std::max(0.0, 1.0 - z * z));
  return {s * std::cos(phi), s * std::sin(phi), z};
}

dvec3 corner(const SphericalMesh& mesh, uint32_t triangle, int k) { return dvec3(mesh.points()[mesh.triangles()[triangle][k]]); }

// The exact gnomonic weights of d in triangle t, in double: the triple products det(d, b, c) etc.
std::array<double, 3> exact_weights(const SphericalMesh& mesh, uint32_t t, const dvec3& d) {
  std::array<double, 3> w;
  for (int e = 0; e < 3; ++e) w[e] = glm::dot(d, glm::cross(corner(mesh, t, (e + 1) % 3), corner(mesh, t, (e + 2) % 3)));
  const double total = w[0] + w[1] + w[2];
  for (double& value : w) value /= total;
  return w;
}

// A search over all triangles: per triangle, the signed sine of d's distance inside its nearest edge.
struct BruteForce {
  explicit BruteForce(const SphericalMesh& mesh) : mesh(mesh) {
    for (uint32_t t = 0; t < mesh.triangles().size(); ++t) {
      for (int e = 0; e < 3; ++e) normals.push_back(glm::normalize(glm::cross(corner(mesh, t, (e + 1) % 3), corner(mesh, t, (e + 2) % 3))));
    }
  }
  double margin(uint32_t t, const dvec3& d) const {
    return std::min({glm::dot(normals[3 * t], d), glm::dot(normals[3 * t + 1], d), glm::dot(normals[3 * t + 2], d)});
  }
  const SphericalMesh& mesh;
  std::vector<dvec3> normals;
};

// locate(d) checked against its definition and against the brute-force search.
void check_location(const BruteForce& brute, const Vec3& direction) {
  const SphericalMesh& mesh = brute.mesh;
  const dvec3 d = glm::normalize(dvec3(direction));
  const SphericalMesh::Location location = mesh.locate(direction);
  ASSERT_LT(location.triangle, mesh.triangles().size());
  double sum = 0.0;
  dvec3 reconstructed(0.0);
  for (int k = 0; k < 3; ++k) {
    ASSERT_GE(location.weights[k], 0.0f);
    sum += location.weights[k];
    reconstructed += double(location.weights[k]) * corner(mesh, location.triangle, k);
  }
  EXPECT_NEAR(sum, 1.0, 1e-6);
  // The gnomonic projection of d onto the triangle's plane.
  const dvec3 a = corner(mesh, location.triangle, 0), b = corner(mesh, location.triangle, 1), c = corner(mesh, location.triangle, 2);
  const dvec3 normal = glm::cross(b - a, c - a);
  const dvec3 projected = d * (glm::dot(normal, a) / glm::dot(normal, d));
  EXPECT_LT(glm::length(reconstructed - projected), 1e-5) << "triangle " << location.triangle;
  uint32_t deepest = 0;
  double deepest_margin = -1e300;
  for (uint32_t t = 0; t < mesh.triangles().size(); ++t) {
    const double margin = brute.margin(t, d);
    if (margin > deepest_margin) deepest_margin = margin, deepest = t;
  }
  // Clearly inside one triangle: that one, with its exact weights; near an edge: any triangle it is
  // within tolerance of.
  if (deepest_margin > 4.0 * SphericalMesh::kEdgeTolerance) {
    EXPECT_EQ(location.triangle, deepest);
    const std::array<double, 3> exact = exact_weights(mesh, location.triangle, d);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(location.weights[k], exact[k], 2e-7);
  } else {
    EXPECT_GE(brute.margin(location.triangle, d), -1.01 * SphericalMesh::kEdgeTolerance);
  }
}

void check_nearest(const SphericalMesh& mesh, const Vec3& direction) {
  const dvec3 d(direction);
  double best = -2.0;
  for (const Vec3& p : mesh.points()) best = std::max(best, glm::dot(dvec3(p), d));
  EXPECT_EQ(glm::dot(dvec3(mesh.points()[mesh.nearest_point(direction)]), d), best);
}

std::vector<SphericalMesh> meshes_up_to(int level) {
  std::vector<SphericalMesh> meshes;
  for (int l = 0; l <= level; ++l) {
    meshes.push_back(SphericalMesh::geodesic_vertices(l));
    meshes.push_back(SphericalMesh::geodesic_face_centers(l));
  }
  return meshes;
}

size_t edge_count(const SphericalMesh& mesh) {
  std::map<std::pair<uint32_t, uint32_t>, int> edges;
  for (const auto& t : mesh.triangles()) {
    for (int i = 0; i < 3; ++i) ++edges[{std::min(t[i], t[(i + 1) % 3]), std::max(t[i], t[(i + 1) % 3])}];
  }
  for (const auto& [edge, count] : edges) EXPECT_EQ(count, 2);  // closed: every edge bounds two triangles
  return edges.size();
}

TEST(Geodesic, CountsPerLevel) {
  for (int level = 0; level <= 6; ++level) {
    const size_t power = size_t(1) << (2 * level);
    const SphericalMesh vertices = SphericalMesh::geodesic_vertices(level);
    EXPECT_EQ(vertices.points().size(), 10 * power + 2);
    EXPECT_EQ(vertices.triangles().size(), 20 * power);
    EXPECT_EQ(edge_count(vertices), 30 * power);
    const SphericalMesh centers = SphericalMesh::geodesic_face_centers(level);
    EXPECT_EQ(centers.points().size(), 20 * power);
    EXPECT_EQ(centers.triangles().size(), 40 * power - 4);
    EXPECT_EQ(edge_count(centers), 60 * power - 6);
    // A level's vertices are a prefix of the next level's, so denser sets reuse the coarser samples.
    if (level > 0) {
      const SphericalMesh coarser = SphericalMesh::geodesic_vertices(level - 1);
      EXPECT_TRUE(std::equal(coarser.points().begin(), coarser.points().end(), vertices.points().begin()));
    }
  }
  EXPECT_THROW(SphericalMesh::geodesic_vertices(-1), std::invalid_argument);
  EXPECT_THROW(SphericalMesh::geodesic_vertices(9), std::invalid_argument);
  EXPECT_THROW(SphericalMesh::geodesic_face_centers(9), std::invalid_argument);
}

TEST(Geodesic, UnitPointsCounterClockwiseConvexAndWatertight) {
  int mesh_index = 0;
  for (const SphericalMesh& mesh : meshes_up_to(6)) {
    double highest = -1.0;  // the far corner across an edge, above the triangle's plane
    for (const Vec3& p : mesh.points()) ASSERT_NEAR(glm::length(dvec3(p)), 1.0, 2e-7);
    const auto& triangles = mesh.triangles();
    for (uint32_t t = 0; t < triangles.size(); ++t) {
      const dvec3 a = corner(mesh, t, 0), b = corner(mesh, t, 1), c = corner(mesh, t, 2);
      ASSERT_GT(glm::dot(a, glm::cross(b, c)), 0.0) << "clockwise triangle " << t;
      const dvec3 outward = glm::cross(b - a, c - a);
      for (int e = 0; e < 3; ++e) {
        // Convex across every edge: the neighbour's far corner lies below this triangle's plane, so
        // the mesh is the convex hull (the Delaunay triangulation) that nearest_point's walk needs.
        const uint32_t other = mesh.neighbours()[t][e];
        const auto& o = triangles[other];
        const uint32_t from = triangles[t][(e + 1) % 3], to = triangles[t][(e + 2) % 3];
        const int far = o[0] != from && o[0] != to ? 0 : (o[1] != from && o[1] != to ? 1 : 2);
        highest = std::max(highest, glm::dot(glm::normalize(outward), dvec3(mesh.points()[o[far]]) - a));
        // The neighbour holds this edge's normal negated, bit for bit, and it points into t.
        EXPECT_EQ(mesh.edge_normals()[other][far], -mesh.edge_normals()[t][e]);
        EXPECT_GT(glm::dot(dvec3(mesh.edge_normals()[t][e]), corner(mesh, t, e)), 0.0);
      }
    }
    std::printf("level %d %s: far corners at most %.3g above a neighbour's plane\n", mesh_index / 2,
                mesh_index % 2 ? "face centres" : "vertices", highest);
    // Face centres: the level-0 ones (a dodecahedron) fan planar pentagons, and at every level some
    // quads of a hexagon are cocircular by symmetry (either diagonal is Delaunay): coplanar up to
    // the rounding of the points to float, a few 1e-8. A reflex edge would stand 1e-4 high at level 6.
    EXPECT_LT(highest, mesh_index % 2 ? 3e-7 : 0.0);
    ++mesh_index;
  }
}

// Measured ratio of the largest to the smallest nearest-neighbour angle (vertices, face centres):
// level 1: 1.0000, 1.0000; 2: 1.0349, 1.1932; 3: 1.1462, 1.2565; 4: 1.1821, 1.2736; 5: 1.1919,
// 1.2780; 6: 1.1946, 1.2796, growing ever more slowly with the level. A latitude-longitude grid's
// ratio grows without bound.
TEST(Geodesic, NearlyUniformSpacing) {
  const double vertex_bound = 1.20, center_bound = 1.29;
  for (int level = 1; level <= 6; ++level) {
    for (bool at_centers : {false, true}) {
      const SphericalMesh mesh = at_centers ? SphericalMesh::geodesic_face_centers(level) : SphericalMesh::geodesic_vertices(level);
      double smallest = 10.0, largest = 0.0;
      for (uint32_t p = 0; p < mesh.points().size(); ++p) {
        // The nearest neighbour of a point is among its Delaunay neighbours.
        double nearest = 10.0;
        for (uint32_t q : mesh.point_neighbours(p)) {
          nearest = std::min(nearest, std::acos(std::min(1.0, glm::dot(dvec3(mesh.points()[p]), dvec3(mesh.points()[q])))));
        }
        smallest = std::min(smallest, nearest), largest = std::max(largest, nearest);
      }
      std::printf("level %d %s: nearest-neighbour angle %.5f .. %.5f rad, ratio %.4f\n", level,
                  at_centers ? "face centres" : "vertices", smallest, largest, largest / smallest);
      EXPECT_LT(largest / smallest, at_centers ? center_bound : vertex_bound) << "level " << level;
    }
  }
}

TEST(Geodesic, LocateRandomDirectionsAgreesWithBruteForce) {
  Random random(7, 0);
  for (int level : {0, 1, 2, 3, 4, 6}) {
    for (bool at_centers : {false, true}) {
      const SphericalMesh mesh = at_centers ? SphericalMesh::geodesic_face_centers(level) : SphericalMesh::geodesic_vertices(level);
      const BruteForce brute(mesh);
      const int count = level >= 6 ? 1000 : 3000;
      for (int i = 0; i < count; ++i) {
        const Vec3 d(random_direction(random));
        check_location(brute, d);
        check_nearest(mesh, d);
        if (testing::Test::HasFailure()) return;
      }
    }
  }
}

TEST(Geodesic, LocateAtPointsIsExactlyOneHot) {
  for (const SphericalMesh& mesh : meshes_up_to(6)) {
    for (uint32_t p = 0; p < mesh.points().size(); ++p) {
      const SphericalMesh::Location location = mesh.locate(mesh.points()[p]);
      const auto& t = mesh.triangles()[location.triangle];
      const int at = static_cast<int>(std::find(t.begin(), t.end(), p) - t.begin());
      ASSERT_LT(at, 3) << "point " << p << " not a corner of its triangle";
      for (int k = 0; k < 3; ++k) ASSERT_EQ(location.weights[k], k == at ? 1.0f : 0.0f);
      ASSERT_EQ(mesh.nearest_point(mesh.points()[p]), p);
      const SphericalMesh::Corners corners = mesh.weighted_corners(mesh.points()[p]);
      ASSERT_EQ(corners.points[0], p);
      ASSERT_EQ(corners.weights[0], 1.0f);
    }
  }
}

TEST(Geodesic, LocateOnEdgesGivesZeroToTheOppositeCorner) {
  double farthest = 0.0;  // off the edge's great circle, of the float directions built on it
  for (const SphericalMesh& mesh : meshes_up_to(6)) {
    const auto& triangles = mesh.triangles();
    for (uint32_t t = 0; t < triangles.size(); ++t) {
      for (int e = 0; e < 3; ++e) {
        const Vec3 a = mesh.points()[triangles[t][(e + 1) % 3]], b = mesh.points()[triangles[t][(e + 2) % 3]];
        for (float along : {0.5f, 0.1f, 0.7f}) {
          if (along != 0.5f && triangles.size() > 5120) continue;
          const Vec3 d = glm::normalize((1.0f - along) * a + along * b);
          farthest = std::max(farthest, std::fabs(glm::dot(glm::normalize(glm::cross(dvec3(a), dvec3(b))), dvec3(d))));
          const SphericalMesh::Location location = mesh.locate(d);
          const auto& found = triangles[location.triangle];
          float on_edge = 0.0f;
          for (int k = 0; k < 3; ++k) {
            if (found[k] == triangles[t][(e + 1) % 3] || found[k] == triangles[t][(e + 2) % 3]) {
              on_edge += location.weights[k];
            } else {
              ASSERT_EQ(location.weights[k], 0.0f) << "triangle " << t << " edge " << e;
            }
          }
          ASSERT_EQ(on_edge, 1.0f);
          // The two corners on the edge share the weight as the exact gnomonic weights do.
          const std::array<double, 3> exact = exact_weights(mesh, location.triangle, dvec3(d));
          double exact_on_edge = 0.0;
          for (int k = 0; k < 3; ++k) exact_on_edge += location.weights[k] > 0.0f ? exact[k] : 0.0;
          for (int k = 0; k < 3; ++k) {
            if (location.weights[k] > 0.0f) {
              ASSERT_NEAR(location.weights[k], exact[k] / exact_on_edge, 2e-7);
            }
          }
          ASSERT_EQ(mesh.weighted_corners(d).weights[2], 0.0f);
        }
      }
    }
  }
  std::printf("float directions built on edges lie up to %.3g rad off them (tolerance %.3g)\n", farthest,
              SphericalMesh::kEdgeTolerance);
  EXPECT_LT(farthest, 0.25 * SphericalMesh::kEdgeTolerance);
}

TEST(Geodesic, LocateAntipodesAxesAndTableSeams) {
  for (int level : {0, 1, 4, 6}) {
    for (bool at_centers : {false, true}) {
      const SphericalMesh mesh = at_centers ? SphericalMesh::geodesic_face_centers(level) : SphericalMesh::geodesic_vertices(level);
      std::vector<Vec3> directions;
      const size_t stride = std::max<size_t>(1, mesh.points().size() / 200);
      for (size_t p = 0; p < mesh.points().size(); p += stride) directions.push_back(-mesh.points()[p]);
      for (int axis = 0; axis < 3; ++axis) {
        for (float sign : {1.0f, -1.0f}) {
          Vec3 d(0.0f);
          d[axis] = sign;
          directions.push_back(d);
        }
      }
      // Cube edges and corners (face seams), then texel boundaries on every face, and just either side.
      for (float x : {-1.0f, 0.0f, 1.0f}) {
        for (float y : {-1.0f, 0.0f, 1.0f}) {
          for (float z : {-1.0f, 0.0f, 1.0f}) {
            if (std::fabs(x) + std::fabs(y) + std::fabs(z) >= 2.0f) directions.push_back(glm::normalize(Vec3(x, y, z)));
          }
        }
      }
      const int n = mesh.table_resolution();
      for (int face = 0; face < 6; ++face) {
        for (int i = 0; i <= n; i += std::max(1, n / 16)) {
          for (float shift : {0.0f, 1e-7f, -1e-7f}) {
            const float u = -1.0f + 2.0f * i / n + shift, v = -1.0f + 2.0f * ((i * 7) % (n + 1)) / n;
            for (const Vec3& along : {Vec3(1.0f, u, v), Vec3(1.0f, v, u), Vec3(1.0f, u, u)}) {
              Vec3 d;
              d[face / 2] = face % 2 ? -along[0] : along[0];
              d[(face / 2 + 1) % 3] = along[1];
              d[(face / 2 + 2) % 3] = along[2];
              directions.push_back(glm::normalize(d));
            }
          }
        }
      }
      const BruteForce brute(mesh);
      for (const Vec3& d : directions) {
        check_location(brute, d);
        check_nearest(mesh, d);
        if (testing::Test::HasFailure()) return;
      }
    }
  }
}

TEST(Geodesic, LookupTableCostAndMemory) {
  for (int level : {0, 4, 6}) {
    const SphericalMesh mesh = SphericalMesh::geodesic_vertices(level);
    std::printf("level %d: table %d^2 x 6 texels, %.2f candidates per texel, %zu bytes\n", level,
                mesh.table_resolution(), mesh.mean_candidates(), mesh.memory_bytes());
    EXPECT_LT(mesh.mean_candidates(), 12.0);
    const size_t texels = 6 * size_t(mesh.table_resolution()) * mesh.table_resolution();
    EXPECT_GE(mesh.memory_bytes(), mesh.points().size() * sizeof(Vec3) + mesh.triangles().size() * (12 + 36 + 12) +
                                       (texels + mesh.mean_candidates() * texels) * sizeof(uint32_t));
  }
}

// locate's cost as geodesic.h states it: a table read, then one triangle tested for most directions.
// Measured over 200,000 random directions at levels 0, 2, 4 and 6: 0.630 to 0.693 of the lookups on the
// vertex meshes, 0.568 to 0.641 on the face-centre meshes; asserted above one half for each.
TEST(Geodesic, MostLookupsTestOneTriangle) {
  Random random(11, 2);
  std::vector<Vec3> directions(200000);
  for (Vec3& d : directions) d = Vec3(random_direction(random));
  for (int level : {0, 2, 4, 6}) {
    for (bool at_centers : {false, true}) {
      const SphericalMesh mesh = at_centers ? SphericalMesh::geodesic_face_centers(level) : SphericalMesh::geodesic_vertices(level);
      size_t first = 0;
      for (const Vec3& d : directions) first += mesh.located_at_first_candidate(d) ? 1 : 0;
      const double share = static_cast<double>(first) / directions.size();
      std::printf("level %d %s: %.3f of lookups test one triangle\n", level, at_centers ? "face centres" : "vertices", share);
      EXPECT_GT(share, 0.5) << "level " << level << (at_centers ? " face centres" : " vertices");
    }
  }
}

// Throughput of locate and nearest_point, in thread CPU time (the machine is shared), for random
// directions and for a 1024 x 1024 latitude-longitude raster (coherent, as an image's receiver points
// are); run with --gtest_also_run_disabled_tests --gtest_filter='*Throughput*'.
TEST(Geodesic, DISABLED_LocateThroughput) {
  auto cpu_seconds = [] {
    timespec now;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
    return now.tv_sec + 1e-9 * now.tv_nsec;
  };
  Random random(3, 1);
  std::vector<Vec3> shuffled(1 << 20), raster;
  for (Vec3& d : shuffled) d = Vec3(random_direction(random));
  for (int i = 0; i < 1024; ++i) {
    for (int j = 0; j < 1024; ++j) {
      const double theta = (i + 0.5) / 1024 * kPiDouble, phi = (j + 0.5) / 1024 * 2 * kPiDouble;
      raster.push_back(Vec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)));
    }
  }
  for (int level : {4, 6}) {
    for (bool at_centers : {false, true}) {
      const SphericalMesh mesh = at_centers ? SphericalMesh::geodesic_face_centers(level) : SphericalMesh::geodesic_vertices(level);
      for (int kind = 0; kind < 4; ++kind) {
        const std::vector<Vec3>& directions = kind % 2 ? raster : shuffled;
        uint64_t checksum = 0;
        double best = 0.0;
        for (int repeat = 0; repeat < 5; ++repeat) {
          const double start = cpu_seconds();
          for (const Vec3& d : directions) checksum += kind < 2 ? mesh.locate(d).triangle : mesh.nearest_point(d);
          best = std::max(best, directions.size() / (cpu_seconds() - start) * 1e-6);
        }
        std::printf("level %d %-12s %-13s %-7s %5.1f million per second (best of 5; checksum %llu)\n", level,
                    at_centers ? "face centres" : "vertices", kind < 2 ? "locate" : "nearest_point", kind % 2 ? "raster" : "random",
                    best, static_cast<unsigned long long>(checksum));
      }
    }
  }
}

// ---- Spherical harmonics.

TEST(SphericalHarmonics, CountsIndexOrderAndRange) {
  EXPECT_EQ(coefficient_count(1), 1);
  EXPECT_EQ(coefficient_count(5), 25);  // the paper's 5th order
  EXPECT_EQ(coefficient_count(10), 100);
  EXPECT_EQ(coefficient_index(1, -1), 1);
  EXPECT_EQ(coefficient_index(2, 2), 8);
  EXPECT_THROW(coefficient_count(0), std::invalid_argument);
  EXPECT_THROW(coefficient_count(11), std::invalid_argument);
  float out[100];
  EXPECT_THROW(evaluate(11, Vec3(0.0f, 0.0f, 1.0f), out), std::invalid_argument);
  EXPECT_THROW(reconstruct(3, std::vector<double>(8, 0.0), dvec3(0.0, 0.0, 1.0)), std::invalid_argument);
}

TEST(SphericalHarmonics, MatchesClosedFormsUpToBandThree) {
  Random random(11, 0);
  for (int i = 0; i < 200; ++i) {
    const dvec3 d = random_direction(random);
    const double x = d.x, y = d.y, z = d.z, pi = kPiDouble;
    const double expected[16] = {
        0.5 / std::sqrt(pi),
        std::sqrt(3 / (4 * pi)) * y, std::sqrt(3 / (4 * pi)) * z, std::sqrt(3 / (4 * pi)) * x,
        std::sqrt(15 / (4 * pi)) * x * y, std::sqrt(15 / (4 * pi)) * y * z, std::sqrt(5 / (16 * pi)) * (3 * z * z - 1),
        std::sqrt(15 / (4 * pi)) * x * z, std::sqrt(15 / (16 * pi)) * (x * x - y * y),
        std::sqrt(35 / (32 * pi)) * (3 * x * x * y - y * y * y), std::sqrt(105 / (4 * pi)) * x * y * z,
        std::sqrt(21 / (32 * pi)) * y * (5 * z * z - 1), std::sqrt(7 / (16 * pi)) * (5 * z * z * z - 3 * z),
        std::sqrt(21 / (32 * pi)) * x * (5 * z * z - 1), std::sqrt(105 / (16 * pi)) * (x * x - y * y) * z,
        std::sqrt(35 / (32 * pi)) * (x * x * x - 3 * x * y * y)};
    double values[16];
    float float_values[16];
    evaluate(4, d, values);
    evaluate(4, Vec3(d), float_values);
    for (int k = 0; k < 16; ++k) {
      ASSERT_NEAR(values[k], expected[k], 1e-14) << "k " << k;
      ASSERT_NEAR(float_values[k], expected[k], 2e-6) << "k " << k;
    }
  }
}

TEST(SphericalHarmonics, OrthonormalUnderTheProductQuadrature) {
  for (int bands = 1; bands <= kMaxBands; ++bands) {
    const SphereQuadrature quadrature = product_quadrature(bands);
    const int count = coefficient_count(bands);
    std::vector<double> gram(count * count, 0.0), basis(count);
    double total = 0.0, z_power = 0.0, x_power = 0.0;
    for (size_t i = 0; i < quadrature.directions.size(); ++i) {
      const dvec3& d = quadrature.directions[i];
      evaluate(bands, d, basis.data());
      for (int j = 0; j < count; ++j) {
        for (int k = 0; k < count; ++k) gram[j * count + k] += quadrature.weights[i] * basis[j] * basis[k];
      }
      total += quadrature.weights[i];
      z_power += quadrature.weights[i] * std::pow(d.z, 2 * bands);
      x_power += quadrature.weights[i] * std::pow(d.x, 2 * bands);
    }
    for (int j = 0; j < count; ++j) {
      for (int k = 0; k < count; ++k) ASSERT_NEAR(gram[j * count + k], j == k ? 1.0 : 0.0, 1e-10) << bands << ": " << j << ", " << k;
    }
    EXPECT_NEAR(total, 4 * kPiDouble, 1e-12);
    // Exact to degree 2 bands, as stated: the integral of z^(2n) (and x^(2n)) is 4 pi / (2n + 1).
    EXPECT_NEAR(z_power, 4 * kPiDouble / (2 * bands + 1), 1e-12);
    EXPECT_NEAR(x_power, 4 * kPiDouble / (2 * bands + 1), 1e-12);
  }
}

std::vector<double> random_coefficients(int bands, Random& random) {
  std::vector<double> c(coefficient_count(bands));
  for (double& value : c) value = 2.0 * random.uniform_double() - 1.0;
  return c;
}

TEST(SphericalHarmonics, ProjectionRecoversBandLimitedFunctions) {
  Random random(5, 0);
  for (int bands = 1; bands <= kMaxBands; ++bands) {
    const std::vector<double> c = random_coefficients(bands, random);
    const SphereQuadrature quadrature = product_quadrature(bands);
    std::vector<double> values;
    for (const dvec3& d : quadrature.directions) values.push_back(reconstruct(bands, c, d));
    const std::vector<double> projected = project(bands, quadrature.directions, quadrature.weights, values);
    for (size_t k = 0; k < c.size(); ++k) ASSERT_NEAR(projected[k], c[k], 1e-10) << bands << " bands, k " << k;
    for (int i = 0; i < 50; ++i) {
      const dvec3 d = random_direction(random);
      EXPECT_NEAR(reconstruct(bands, projected, d), reconstruct(bands, c, d), 1e-11);
    }
  }
}

TEST(SphericalHarmonics, BandEnergiesAreRotationInvariant) {
  Random random(9, 0);
  for (int bands = 2; bands <= kMaxBands; ++bands) {
    const std::vector<double> c = random_coefficients(bands, random);
    const SphereQuadrature quadrature = product_quadrature(bands);
    std::vector<double> values;
    for (const dvec3& d : quadrature.directions) values.push_back(reconstruct(bands, c, d));
    const glm::dquat turn = glm::normalize(glm::dquat(2.0 * random.uniform_double() - 1.0, random_direction(random)));
    std::vector<dvec3> turned;
    for (const dvec3& d : quadrature.directions) turned.push_back(turn * d);
    const std::vector<double> rotated = project(bands, turned, quadrature.weights, values);
    const std::vector<double> before = band_energies(bands, c), after = band_energies(bands, rotated);
    for (int l = 0; l < bands; ++l) ASSERT_NEAR(after[l], before[l], 1e-9) << bands << " bands, l " << l;
    double change = 0.0;  // the rotation did move the coefficients: the check is not vacuous
    for (size_t k = 0; k < c.size(); ++k) change = std::max(change, std::fabs(rotated[k] - c[k]));
    EXPECT_GT(change, 1e-2);
  }
}

}  // namespace
}  // namespace causticbench::lpi
