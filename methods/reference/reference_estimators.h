// The reference's two estimators of a pixel's caustic irradiance (docs/metrics.md, "A pixel's E_c") and
// the estimate of their error:
// - footprint: every deposited photon the camera sees is credited to the pixel whose footprint holds it,
//   weighted by the image area per surface area there. No radius, so no radius bias: its error is its
//   variance, estimated per pixel from the spread of independent passes (stratified emission) or from
//   the second moment of the photons' contributions (random emission).
// - ppm: progressive photon mapping (Hachisuka, Ogaki and Jensen 2008) at the pixel centres, in two
//   independent halves whose difference measures its variance. Its bias against the pixel's footprint
//   average is estimated from a footprint tally of the same photons.
// Why our own code: these estimators and their error are the subject of the reference (issue 29); no
// library computes them.
#pragma once

#include <cstdint>
#include <vector>

#include "core/camera.h"
#include "core/gbuffer.h"
#include "core/image.h"
#include "core/photon_tracer.h"

namespace causticbench {

// The receiver pixels of a G-buffer, in pixel order.
struct MeasurementPoints {
  int width = 0, height = 0;
  std::vector<uint32_t> pixel;
  std::vector<Vec3> position;
  std::vector<Vec3> normal;
  std::vector<int32_t> point_of_pixel;  // index into the vectors above, -1 where the pixel is no receiver
  explicit MeasurementPoints(const GBuffer& gbuffer);
  size_t size() const { return pixel.size(); }
};

// Sums of each point's photon contributions and of their squares (W/m^2 times photons emitted), and of
// each replicate's estimate and its square: a replicate is a batch of photons independent of the others
// (a pass of stratified emission, whose photons are not independent of each other), so that the spread of
// the replicates measures the variance of their mean where the photons' second moment would overstate it.
class FootprintTally {
 public:
  explicit FootprintTally(size_t points)
      : sum_(points, glm::dvec3(0.0)), sum_squares_(points, glm::dvec3(0.0)), replicate_sum_(points, glm::dvec3(0.0)),
        replicate_values_(points, glm::dvec3(0.0)), replicate_squares_(points, glm::dvec3(0.0)) {}
  // Credits the photons of one batch: projects each through the camera, keeps it when the camera sees
  // the side it arrived on with nothing in between and its pixel is a receiver. Deterministic for any
  // thread count (the sums run in photon order). Returns how many were credited.
  // With `targets`, it receives each photon's point (-1: not credited); with `weights`, each photon's
  // pixels per unit area there (what its power is credited times: 0 where not credited).
  uint64_t credit(const MeasurementPoints& points, const CameraFrame& camera, const Tracer& tracer,
                  const std::vector<Photon>& photons, std::vector<int32_t>* targets = nullptr,
                  std::vector<double>* weights = nullptr);
  // Each photon's point as credit() finds it (-1: not in view), without crediting it: where light that an
  // occluder blocked would have been seen (PathClassTally).
  static std::vector<int32_t> locate(const MeasurementPoints& points, const CameraFrame& camera, const Tracer& tracer,
                                     const std::vector<Photon>& photons, std::vector<double>* pixels_per_area = nullptr);
  // Ends the current replicate, of `emitted` photons (every photon credited since the last call).
  void end_replicate(uint64_t emitted);
  uint64_t emitted() const { return emitted_; }
  uint64_t replicates() const { return replicates_; }
  // The estimate (mean contribution per photon emitted) per point and channel.
  glm::dvec3 value(size_t point) const;
  // Its variance from the photons' second moment, for independent photons (random emission). Deposits
  // of one path in one pixel count as independent samples (only a diffuse+mirror receiver makes a path
  // deposit twice), which slightly underestimates the variance there.
  glm::dvec3 photon_variance(size_t point) const;
  // Its variance from the spread of the replicates (equal in size), for any emission; needs two.
  glm::dvec3 replicate_variance(size_t point) const;

 private:
  std::vector<glm::dvec3> sum_, sum_squares_;
  std::vector<glm::dvec3> replicate_sum_, replicate_values_, replicate_squares_;
  uint64_t emitted_ = 0, replicates_ = 0;
};

// One progressive photon mapping estimator over the points (Hachisuka et al. 2008, Section 4.2):
// accumulated photon count N, squared radius R^2 and radius-corrected flux tau per point.
class ProgressiveEstimator {
 public:
  ProgressiveEstimator(const MeasurementPoints& points, const GBuffer& gbuffer, double initial_radius_pixels);
  // Gathers one pass of photons, then shrinks each radius keeping the fraction alpha of the new ones.
  void gather(const MeasurementPoints& points, const std::vector<Photon>& photons, double alpha);
  void add_emitted(uint64_t count) { emitted_ += count; }
  glm::dvec3 value(size_t point) const;

 private:
  std::vector<double> count_;
  std::vector<float> radius2_;
  std::vector<glm::dvec3> flux_;
  uint64_t emitted_ = 0;
};

// Per point and channel: the value, and the expected squared error of the value (variance plus
// squared bias where the estimator has a bias).
struct ErrorImage {
  std::vector<glm::dvec3> value, squared_error, variance;
};

// The estimate of relMSE (core/image_statistics.h, with the value itself standing in for the unknown
// truth) that a squared error per point gives: mean over points and channels of e^2 / (v^2 + epsilon).
double estimated_relative_mse(const std::vector<glm::dvec3>& value, const std::vector<glm::dvec3>& squared_error);

// Writes per-point values (or, with `root`, square roots of them) into an RGB image at their pixels.
void write_points(const MeasurementPoints& points, const std::vector<glm::dvec3>& values, bool root, Image& image);

}  // namespace causticbench
