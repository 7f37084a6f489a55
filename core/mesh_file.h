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

}  // namespace causticbench
