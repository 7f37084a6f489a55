// One posed frame of a scene, written for a program outside causticbench (the `external` method,
// methods/external/): self-contained files in one folder, documented in methods/external/README.md.
//
//   scene.json   a causticbench scene (docs/scene-format.md, in JSON, which the YAML reader reads): the
//                scene as posed at the frame, every animation track replaced by its value there, `frames`
//                1, every mesh and environment map written beside it. `causticbench render scene.json`
//                reads it back into the same geometry, lights and camera bit for bit, so a program may be
//                causticbench itself (tests/test_external.cpp checks photon_map through it).
//   world.json   the same frame in world space, for renderers of their own: the camera, each light posed
//                (the unit direction towards a distant light, a point light's position), each object's
//                shape and material as in scene.json with its object-to-world matrix, its world bounding
//                sphere, whether it makes or receives caustics, and for the triangle shapes (quad, box,
//                prism, torus, water, mesh) a PLY file of its world-space triangles and vertex normals.
//
// Written with atomic renames, so that a program never reads half a file of a previous frame.
#pragma once

#include <map>
#include <string>

#include "core/scene.h"

namespace causticbench {

class SceneExporter {
 public:
  // Writes into `folder` (which must exist); files that do not change from one frame to the next (an
  // object-space mesh, an environment map, the world triangles of an object that has not moved) are
  // written once.
  explicit SceneExporter(std::string folder);
  // Writes scene.json and world.json of `frame`; returns the path of scene.json.
  std::string write(const SceneFrame& frame);
  std::string scene_path() const { return folder_ + "/scene.json"; }
  std::string world_path() const { return folder_ + "/world.json"; }

 private:
  std::string folder_;
  // File name -> the description of what was last written there (a hash of its content's source), so
  // that unchanged files are not written again.
  std::map<std::string, std::string> written_;
};

}  // namespace causticbench
