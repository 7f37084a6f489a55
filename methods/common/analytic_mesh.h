// Triangle meshes of the analytic shapes (sphere, disk, ring, cup, paraboloid), which the ray tracer
// intersects exactly but a method built on triangles (caustic volumes' beams, a rasteriser's light
// views) needs tessellated. Vertices lie on the exact surface with its exact normals; vertices are
// shared between neighbouring triangles (a closed seam, one vertex per pole), so that a per-vertex
// quantity is one value where triangles meet.
#pragma once

#include "core/shape.h"

namespace causticbench {

// `segments` quads around the shape's axis (at least 3); along it: a sphere segments / 2 rings, a ring's
// or cup's wall and a disk, paraboloid or cup bottom max(1, segments / 8) rows (Ernst et al.'s ring:
// 64 around, 8 high, 2 x 64 x 8 triangles). Object space; smooth (vertex normals are the surface's).
// Not for the non-analytic shapes (core/shape.h's tessellate() makes those).
TriangleMesh tessellate_analytic(const ShapeDesc& shape, int segments);

}  // namespace causticbench
