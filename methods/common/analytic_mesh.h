// Triangle meshes of the analytic shapes (sphere, disk, ring, cup, paraboloid), which the ray tracer
// intersects exactly but a method built on triangles (caustic volumes' beams, a rasteriser's light
// views) needs tessellated. Vertices lie on the exact surface with its exact normals; vertices are
// shared between neighbouring triangles (a closed seam, one vertex per pole), so that a per-vertex
// quantity is one value where triangles meet.
#pragma once

#include <vector>

#include <glm/vec3.hpp>

#include "core/scene.h"
#include "core/shape.h"

namespace causticbench {

// `segments` quads around the shape's axis (at least 3); along it: a sphere segments / 2 rings, a ring's
// or cup's wall and a disk, paraboloid or cup bottom max(1, segments / 8) rows (Ernst et al.'s ring:
// 64 around, 8 high, 2 x 64 x 8 triangles). Object space; smooth (vertex normals are the surface's).
// Not for the non-analytic shapes (core/shape.h's tessellate() makes those).
TriangleMesh tessellate_analytic(const ShapeDesc& shape, int segments);

// An object's triangles in world space, vertices shared where the surface is smooth (the one-ring of a
// vertex is its triangles); a flat-shaded mesh has its own three vertices per triangle, with its normal.
struct SurfaceMesh {
  std::vector<glm::dvec3> positions, normals;
  std::vector<glm::uvec3> triangles;
};

// The object's mesh at this frame: an analytic shape tessellated with `segments` (above), otherwise the
// scene's own triangles (what the ray tracer intersects). Caustic volumes build their beams on it; the
// rasterised light views of caustics mapping draw it.
// `subdivide_flat_solids`: a box's or prism's faces are cut like a sphere's, each of its triangles into
// n x n with n = max(1, segments / 4) (a box's four sides around its axis are then about `segments`
// edges, as a sphere's equator is): a beam spanning a whole face would send its corner rays out through
// different faces and tear (caustic volumes). The cut triangles lie in the face, flat-shaded, so the
// surface is the same; only where the beams are drawn changes.
SurfaceMesh surface_mesh(const SceneFrame& frame, int object, int segments, bool subdivide_flat_solids = false);

// Each triangle of a flat-shaded mesh (its own three vertices) cut into n x n triangles of the same plane
// and winding, each with the parent's normal.
SurfaceMesh subdivide_flat(const SurfaceMesh& flat, int n);

}  // namespace causticbench
