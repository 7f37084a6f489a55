// Point samples on the reflector surfaces (Wand & Strasser 2003, Section 3.2) and their differential
// geometry (Section 3.3). Each sample stands for a small patch of area A / N that acts as a pinhole
// camera projecting the incoming light onto the receivers.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/sampling.h"
#include "core/scene.h"

namespace causticbench {

struct SurfacePoint {
  Vec3 position;
  Vec3 normal;  // unit, outward
  int object = -1;
};

struct ReflectorSample {
  Vec3 position;
  Vec3 normal;
  float area = 0.0f;       // A / N
  int object = -1;
  bool two_sided = false;  // open surfaces reflect on both sides
  // Differential point sample: principal directions (unit, in the tangent plane) and the normal's
  // derivative along each; principal curvatures for checks.
  Vec3 direction_u{0.0f}, direction_v{0.0f};
  Vec3 normal_derivative_u{0.0f}, normal_derivative_v{0.0f};
  float curvature_u = 0.0f, curvature_v = 0.0f;
};

enum class SamplingStrategy { random, grid, quantized_grid, neighborhood };
SamplingStrategy parse_sampling_strategy(const std::string& name);

// Area-uniform random points on the given objects as posed in `frame`. Analytic shapes are sampled
// uniformly in object space and transformed (area-uniform in the world for uniform scales); meshes
// are sampled per world-space triangle. `total_area` receives the summed world area.
std::vector<SurfacePoint> sample_surfaces(const SceneFrame& frame, const std::vector<int>& objects, size_t count,
                                          Random& random, double& total_area);

// World-space area of one posed object.
double object_area(const SceneFrame& frame, int object);

struct SampleSet {
  std::vector<ReflectorSample> samples;
  double total_area = 0.0;
  double spacing = 0.0;        // sqrt(A / N): the sample spacing used for epsilon and the footprint radius
  double cell_or_diameter = 0.0;  // grid cell size or neighbourhood sphere diameter that reached the target
  std::vector<SurfacePoint> dense;  // the dense random set the strategies draw from (kept for curvature)
};

// Draws about `target` samples with the strategy. The dense set has `oversampling` x target points
// (at least 20,000); the cell size or sphere diameter is searched so that the kept count lands within
// 3 % of the target where the strategy allows it.
SampleSet sample_reflectors(const SceneFrame& frame, const std::vector<int>& objects, size_t target,
                            SamplingStrategy strategy, uint64_t seed, int oversampling = 4);

// Fits n(u, v) = n + u dn/du + v dn/dv by linear regression over the dense points within `radius` of
// each sample (same object, normals within 60 degrees), then rotates (u, v) into the principal
// directions (eigenvectors of the symmetrised shape operator).
void estimate_differentials(SampleSet& set, double radius);

}  // namespace causticbench
