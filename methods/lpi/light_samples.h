// The light directions an object's caustic is precomputed for (Wyman 2003, Section 4.1) and, per
// frame, which of them a light direction reads and how (Sections 5.1 and 5.2). Directions are unit
// vectors towards the light in the object's build space (methods/lpi/precompute.h).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <glm/mat3x3.hpp>

#include "core/math.h"
#include "methods/common/geodesic.h"

namespace causticbench::lpi {

enum class SampleAt { vertices, faces };
// none: samples over the whole sphere; axial: an object symmetric about its local y axis needs
// samples on one meridian only (the lookup turns the light about the axis onto it); spherical: one
// sample, the lookup turns any direction onto it.
enum class Symmetry { none, axial, spherical };
enum class Blend { nearest, barycentric, aligned };

struct LightSampleSet {
  std::string kind;    // static, geodesic, environment (part of the geodesic set), meridian, spherical
  std::string reason;  // why this set, for the run record
  std::vector<Vec3> directions;
  std::optional<SphericalMesh> mesh;  // geodesic, environment: the triangulation the blend locates in
  Vec3 axis{0.0f, 1.0f, 0.0f};        // meridian: the symmetry axis
  Vec3 meridian{1.0f, 0.0f, 0.0f};    // meridian: unit, perpendicular to the axis: azimuth 0
  // environment: the mesh point of each sample, and per mesh point its sample or -1 (not shot).
  // Empty otherwise: sample i is mesh point i.
  std::vector<uint32_t> mesh_points;
  std::vector<int32_t> sample_of_point;

  // The sample that holds mesh point `point`, or -1 when the set left it out.
  int32_t sample_of(uint32_t point) const { return sample_of_point.empty() ? static_cast<int32_t>(point) : sample_of_point[point]; }
  // What sample i's photons draw from: its mesh point, so that a part of the geodesic set shoots
  // exactly the photons the whole set would for the same directions.
  uint64_t seed_index(size_t sample) const { return mesh_points.empty() ? sample : mesh_points[sample]; }
};

// The geodesic set: an icosahedron subdivided `level` times, at its vertices or face centres.
LightSampleSet geodesic_samples(int level, SampleAt at);
// The points of a geodesic set for which keep[point] holds (kind environment), in mesh order.
LightSampleSet geodesic_part(LightSampleSet geodesic, const std::vector<bool>& keep);
// Samples on one meridian of `axis`: 5 2^level + 1 polar angles from the axis to its opposite, about
// the spacing of the geodesic set of the same level.
LightSampleSet meridian_samples(int level, const Vec3& axis);

// One volume read for a light: the sample's values at R (p - c) + c, weighted; `rotated` when R is not
// the identity (vector irradiance read there is turned back by R^T).
struct SampleRead {
  uint32_t sample = 0;
  float weight = 0.0f;
  bool rotated = false;
  glm::mat3 rotation{1.0f};
};

struct LightReads {
  int count = 0;
  SampleRead reads[3];
};

// The reads for a light arriving from `direction` (unit). nearest: the sample with the largest dot
// product; barycentric: the three corners of the spherical triangle containing it, with their
// barycentric weights (two neighbours on a meridian); aligned: the same corners, each read at the
// point turned about direction x sample by the angle between them (Section 5.2, steps A to F, then
// the barycentric blend of the three lookups). A static set maps each of its directions to itself.
LightReads light_reads(const LightSampleSet& set, const Vec3& direction, Blend blend);

// The rotation taking unit `from` onto unit `to` about their common perpendicular (identity when
// they are equal; a half turn about some perpendicular when opposite).
glm::mat3 rotation_between(const Vec3& from, const Vec3& to);

}  // namespace causticbench::lpi
