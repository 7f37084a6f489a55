// The precomputation of Wyman 2003 (Section 4.2) for one specular object: photons from a directional
// light of unit irradiance through a disk covering the object's bounding sphere, for every light
// sample, traced through the object alone (its caustic is a local property: another object in the
// way is not part of it), every segment after the first specular bounce added into the sampled
// volume by the layout's track-length estimator.
//
// Build space: methods/common/build_space.h.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <glm/mat3x3.hpp>

#include "core/photon_tracer.h"
#include "core/scene.h"
#include "methods/common/build_space.h"
#include "methods/lpi/light_samples.h"
#include "methods/lpi/multires_layout.h"
#include "methods/common/stored_values.h"
#include "methods/common/volume_layout.h"

namespace causticbench::lpi {

enum class StorageKind { grid, shells, multires, sh };

struct VolumeSettings {
  StorageKind storage = StorageKind::grid;
  int grid_resolution = 64;
  int shell_count = 12;
  int shell_subdivision = 4;
  int shell_spacing = 0;            // ShellSpacing
  int multires_depth = 6;           // finest level: 2^depth cells a side
  double error_threshold = 0.01;    // relative to each light sample's largest value
  MultiresTree multires_tree = MultiresTree::shared;  // one tree for all light samples, or one each
  int sh_order = 4;                 // highest degree of the spherical harmonics
  double volume_radius = 0.0;       // in bounding radii; 0: auto (volume_radius.h chooses it per object)
  Orientation orientation = Orientation::paper;
  bool orientation_auto = false;     // auto: `orientation` is what plan() resolved (orientation_choice.h)
  Precision precision = Precision::float32;
  uint64_t photons_per_sample = 1000000;
  uint64_t seed = 1;
};


struct ObjectVolumes {
  int object = -1;
  std::string name;
  BoundingSphere bounds;  // of the object, build space
  double volume_radius = 3.0;        // the sampled ball's radius in bounding radii (volume_radius.h)
  std::string volume_radius_reason;  // why: the number set, or what auto measured
  LightSampleSet samples;
  std::unique_ptr<VolumeLayout> layout;
  // Light-sample blocks, or for storage: sh one block per spherical-harmonic coefficient.
  StoredValues values;
  bool harmonic = false;  // values are spherical-harmonic coefficient blocks
  PhotonStats stats;
  double shoot_seconds = 0.0;  // photon shooting and deposition, all light samples
};

inline bool per_sample_trees(const VolumeSettings& settings) {
  return settings.storage == StorageKind::multires && settings.multires_tree == MultiresTree::per_sample;
}

// The layout of a ball of `radius` bounding radii around `bounds`' centre.
std::unique_ptr<VolumeLayout> make_layout(const VolumeSettings& settings, const BoundingSphere& bounds, double radius);

// Blocks of stored values: one per light sample, or per coefficient for storage: sh.
size_t stored_blocks(const VolumeSettings& settings, const ObjectVolumes& volumes);
// Stored bytes per light sample: its block and its share of the table that indexes the values (the
// multires tree); for storage: sh, every coefficient's bytes shared among the light samples fitted;
// for a multires tree per light sample, the mean over the samples of each one's leaves and tree.
double bytes_per_light_sample(const ObjectVolumes& volumes);

// Computes volumes.values for every direction of volumes.samples: photons_per_sample photons per
// light sample, photon i of sample s drawing only from Random(seed, s 2^32 + i) (s: its
// LightSampleSet::seed_index) and summed in fixed chunks, so that the result does not depend on the
// thread count. An adaptive layout then adapts to
// every sample's values; storage: sh fits its coefficients to them. `report(done, total)` after each
// light sample.
void shoot_light_samples(const Scene& build_scene, const VolumeSettings& settings, ObjectVolumes& volumes,
                         const std::function<void(size_t, size_t)>& report);

}  // namespace causticbench::lpi
