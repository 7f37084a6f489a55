// Reading a mesh file (OBJ, PLY and whatever else Assimp reads) into a TriangleMesh, with the checks that
// keep non-finite or huge vertices out of the ray tracer (issue 30): what a scene's `type: mesh` loads.
#pragma once

#include <memory>
#include <string>

#include "core/config.h"
#include "core/shape.h"

namespace causticbench {

// The meshes of the file at `path`, triangulated and joined into one; smooth normals (Assimp's) or flat
// ones; scaled so that the largest extent is fit_size, centred in x and z and standing on y = 0 when
// fit_size > 0. Throws InputError naming `where` (the scene line), the file and the defect.
std::shared_ptr<const TriangleMesh> load_mesh(const std::string& path, bool smooth_normals, double fit_size,
                                              const SourceLocation& where);

// Writes `mesh` as a binary little-endian PLY (Assimp's exporter): positions, vertex normals (when the
// mesh has them) and triangles, in single precision as held, so that load_mesh reads back the same
// triangles and normals (its joining of identical vertices may renumber the vertices, never move them).
// Atomic; WriteError naming the file on failure.
void write_mesh_ply(const TriangleMesh& mesh, const std::string& path);

}  // namespace causticbench
