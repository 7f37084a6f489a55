// Bundle extraction (Liu et al. 2008, Section 3.1.1): the caustic object rays' lines rasterised into
// an extended grid around the object by a 3D DDA, the cell of most energy seeding an axis, rays
// assigned to it by line distance and angle, the axis refitted by least squares, repeated to
// convergence. The caller fits a spot light to each bundle, dismisses the rays it cannot represent
// and removes the rest (methods/csl/generate.cpp).
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "methods/csl/object_rays.h"

namespace causticbench::csl {

struct BundleSettings {
  int raster_resolution = 64;      // cells along each axis of the extended grid
  double raster_half_size = 4.0;   // scene units: half the side of the grid's cube, centred on the object
  double distance_threshold = 0.1; // scene units: largest distance between a ray's line and the axis
  double cos_angle_threshold = 0;  // smallest cosine between a ray and the axis (cos 90 deg, the paper's)
  int max_iterations = 100;        // the paper's cap (it saw about 15)
};

struct BundleAxis {
  glm::dvec3 origin{0.0};
  glm::dvec3 direction{0.0, 0.0, 1.0};  // unit
};

// The energy of every ray's line in each cell of a cube, kept as rays are removed.
class RayRaster {
 public:
  RayRaster(const Vec3& center, double half_size, int resolution);
  // Adds `sign` times the ray's weight to every cell its line crosses.
  void add(const CausticRay& ray, double sign);
  // The cell of most energy, or -1 when no cell holds more than `floor`.
  int richest_cell(double floor) const;
  double energy(int cell) const { return energy_[cell]; }
  // The cell's box.
  void cell_box(int cell, glm::dvec3& low, glm::dvec3& high) const;
  // Empties a cell for good (a seed that gave no bundle is not tried again).
  void retire(int cell) { retired_[cell] = 1; }
  int resolution() const { return resolution_; }

 private:
  glm::dvec3 low_;
  double cell_ = 0.0;
  int resolution_ = 0;
  std::vector<double> energy_;
  std::vector<uint8_t> retired_;
};

// Whether the line of `ray` passes through the box.
bool line_crosses_box(const CausticRay& ray, const glm::dvec3& low, const glm::dvec3& high);
// Distance between the line of `ray` and the axis's line.
double line_distance(const CausticRay& ray, const BundleAxis& axis);

struct Bundle {
  BundleAxis axis;
  std::vector<uint32_t> members;  // indices into the rays
  int iterations = 0;
  bool converged = false;
};

// Grows the bundle seeded by `cell` among the rays still `active`: steps 2 to 5.
Bundle grow_bundle(const std::vector<CausticRay>& rays, const std::vector<uint8_t>& active, const RayRaster& raster,
                   int cell, const BundleSettings& settings);

// Steps 3 to 5 from a given axis: what grow_bundle does after its seed, and what tracking a spot
// light's axis to a neighbouring light direction does at each step (Section 4.2, step 3).
Bundle refine_bundle(const std::vector<CausticRay>& rays, const std::vector<uint8_t>& active, const BundleAxis& start,
                     const BundleSettings& settings);

// Step 4: the energy-weighted mean direction, and the point nearest all members' lines in the least
// squares sense (pulled very slightly to their mean origin, so that a parallel bundle, whose lines
// have no nearest point along their direction, stays determined).
BundleAxis optimise_axis(const std::vector<CausticRay>& rays, const std::vector<uint32_t>& members);

}  // namespace causticbench::csl
