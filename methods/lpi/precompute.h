// The precomputation of Wyman 2003 (Section 4.2) for one specular object: photons from a directional
// light of unit irradiance through a disk covering the object's bounding sphere, for every light
// sample, traced through the object alone (its caustic is a local property: another object in the
// way is not part of it), every segment after the first specular bounce added into the sampled
// volume by the layout's track-length estimator.
//
// Build space: the object scaled as at frame 0, neither rotated nor translated. A frame's world
// point p maps to it by S0 T_f^-1 p (T_f: the object's transform at that frame, S0: its scale at
// frame 0), so the caustic moves and turns with the object and one build serves any placement of it.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <glm/mat3x3.hpp>

#include "core/photon_tracer.h"
#include "core/scene.h"
#include "methods/lpi/light_samples.h"
#include "methods/lpi/stored_values.h"
#include "methods/lpi/volume_layout.h"

namespace causticbench::lpi {

enum class StorageKind { grid, shells };

struct VolumeSettings {
  StorageKind storage = StorageKind::grid;
  int grid_resolution = 64;
  int shell_count = 12;
  int shell_subdivision = 4;
  int shell_spacing = 0;            // ShellSpacing
  double volume_radius = 3.0;       // in bounding radii
  Orientation orientation = Orientation::paper;
  Precision precision = Precision::float32;
  uint64_t photons_per_sample = 1000000;
  uint64_t seed = 1;
};

// A frame's map from world space into an object's build space.
struct BuildSpaceMap {
  glm::mat3 linear{1.0f};   // S0 M_f^-1
  Vec3 offset{0.0f};
  glm::mat3 normals{1.0f};  // inverse transpose of `linear`, for normals (normalise after)
  Vec3 point(const Vec3& p) const { return linear * p + offset; }
  Vec3 vector(const Vec3& v) const { return linear * v; }
};
BuildSpaceMap build_space_map(const SceneObject& object, double frame);

struct ObjectVolumes {
  int object = -1;
  std::string name;
  BoundingSphere bounds;  // of the object, build space
  LightSampleSet samples;
  std::unique_ptr<VolumeLayout> layout;
  StoredValues values;
  PhotonStats stats;
  double shoot_seconds = 0.0;  // photon shooting and deposition, all light samples
};

std::unique_ptr<VolumeLayout> make_layout(const VolumeSettings& settings, const BoundingSphere& bounds);

// The object alone, posed in build space (a scene of one object, for the photon tracer).
Scene build_space_scene(const Scene& scene, int object);

// Computes volumes.values for every direction of volumes.samples: photons_per_sample photons per
// light sample, photon i of sample s drawing only from Random(seed, s 2^32 + i) and summed in fixed
// chunks, so that the result does not depend on the thread count. `report(done, total)` after each
// light sample.
void shoot_light_samples(const Scene& build_scene, const VolumeSettings& settings, ObjectVolumes& volumes,
                         const std::function<void(size_t, size_t)>& report);

}  // namespace causticbench::lpi
