// `storage: sh` (Wyman 2003, Section 4.3 and Fig. 9): per grid cell, the caustic irradiance as a
// function of the light direction, fitted with real spherical harmonics of degree 0 .. sh_order over
// the whole geodesic set of light samples; per frame the basis is evaluated at the light's direction
// and every cell's value is the sum of its coefficients times it.
//
// The fit: weighted least squares over the light samples, each weighted by its share of the sphere
// (a third of the spherical triangles around it in the set's triangulation; they sum to 4 pi).
// With equal weights on an exact quadrature this is the projection c_k = integral of f Y_k; on the
// geodesic set, which no quadrature rule integrates every product of the basis exactly, least
// squares keeps what projection loses: a function of degree <= sh_order is reproduced exactly.
#pragma once

#include <vector>

#include "methods/lpi/light_samples.h"

namespace causticbench::lpi {

// The spherical area around each point of the set's triangulation (its mesh), summing to 4 pi.
std::vector<double> light_sample_areas(const LightSampleSet& set);

class HarmonicFit {
 public:
  // Throws std::invalid_argument when the samples cannot determine (order + 1)^2 coefficients.
  HarmonicFit(int order, const std::vector<Vec3>& directions, const std::vector<double>& weights);
  int bands() const { return bands_; }
  int coefficients() const { return bands_ * bands_; }
  // values: light samples x `per_sample` floats (each sample's block); returns coefficients x
  // per_sample floats, block k holding coefficient k of every value.
  std::vector<float> fit(const std::vector<float>& values, size_t per_sample) const;

 private:
  int bands_;
  size_t samples_;
  std::vector<double> solve_;  // coefficients x samples: (Y^T W Y)^-1 Y^T W
};

}  // namespace causticbench::lpi
