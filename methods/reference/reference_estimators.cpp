#include "methods/reference/reference_estimators.h"

#include <algorithm>
#include <cmath>

#include "core/image_statistics.h"
#include "core/parallel.h"
#include "methods/common/photon_grid.h"
#include "methods/common/photon_view.h"

namespace causticbench {

MeasurementPoints::MeasurementPoints(const GBuffer& gbuffer)
    : width(gbuffer.width), height(gbuffer.height), point_of_pixel(gbuffer.pixel_count(), -1) {
  for (size_t i = 0; i < gbuffer.pixel_count(); ++i) {
    if (!gbuffer.receiver[i]) continue;
    point_of_pixel[i] = static_cast<int32_t>(pixel.size());
    pixel.push_back(static_cast<uint32_t>(i));
    position.push_back(gbuffer.position[i]);
    normal.push_back(gbuffer.normal[i]);
  }
}

std::vector<int32_t> FootprintTally::locate(const MeasurementPoints& points, const CameraFrame& camera,
                                            const Tracer& tracer, const std::vector<Photon>& photons,
                                            std::vector<double>* pixels_per_area) {
  std::vector<int32_t> target(photons.size(), -1);
  if (pixels_per_area) pixels_per_area->assign(photons.size(), 0.0);
  parallel_blocks(photons.size(), 2048, [&](size_t begin, size_t end, size_t) {
    for (size_t i = begin; i < end; ++i) {
      const Photon& photon = photons[i];
      // The pixel test before the shadow ray: most photons of a caustic land outside the receivers' pixels.
      std::optional<CameraFrame::ImagePoint> image = camera.project(photon.position, photon.normal);
      if (!image) continue;
      int32_t point = points.point_of_pixel[static_cast<size_t>(image->y) * points.width + image->x];
      if (point < 0 || !camera_sees(*image, tracer, photon)) continue;
      target[i] = point;
      if (pixels_per_area) (*pixels_per_area)[i] = image->pixels_per_area;
    }
  });
  return target;
}

uint64_t FootprintTally::credit(const MeasurementPoints& points, const CameraFrame& camera, const Tracer& tracer,
                                const std::vector<Photon>& photons, std::vector<int32_t>* targets,
                                std::vector<double>* weights) {
  std::vector<double> weight;
  std::vector<int32_t> target = locate(points, camera, tracer, photons, &weight);
  uint64_t credited = 0;
  for (size_t i = 0; i < photons.size(); ++i) {
    if (target[i] < 0) continue;
    glm::dvec3 contribution = glm::dvec3(photons[i].power) * weight[i];
    sum_[target[i]] += contribution;
    sum_squares_[target[i]] += contribution * contribution;
    replicate_sum_[target[i]] += contribution;
    ++credited;
  }
  if (targets) *targets = std::move(target);
  if (weights) *weights = std::move(weight);
  return credited;
}

void FootprintTally::end_replicate(uint64_t emitted) {
  emitted_ += emitted;
  ++replicates_;
  const double n = static_cast<double>(std::max<uint64_t>(1, emitted));
  for (size_t i = 0; i < replicate_sum_.size(); ++i) {
    const glm::dvec3 value = replicate_sum_[i] / n;
    replicate_values_[i] += value;
    replicate_squares_[i] += value * value;
    replicate_sum_[i] = glm::dvec3(0.0);
  }
}

glm::dvec3 FootprintTally::value(size_t point) const {
  return sum_[point] / static_cast<double>(std::max<uint64_t>(1, emitted_));
}

glm::dvec3 FootprintTally::photon_variance(size_t point) const {
  // Var(mean) = (E[X^2] - E[X]^2) / N over the N photons emitted, most of whose X are zero.
  const double n = static_cast<double>(std::max<uint64_t>(2, emitted_));
  glm::dvec3 mean = sum_[point] / n;
  return glm::max(sum_squares_[point] / n - mean * mean, glm::dvec3(0.0)) / (n - 1.0);
}

glm::dvec3 FootprintTally::replicate_variance(size_t point) const {
  // The sample variance of R independent replicates over R: the variance of their mean.
  const double r = static_cast<double>(std::max<uint64_t>(2, replicates_));
  const glm::dvec3 mean = replicate_values_[point] / r;
  return glm::max(replicate_squares_[point] / r - mean * mean, glm::dvec3(0.0)) / (r - 1.0);
}

ProgressiveEstimator::ProgressiveEstimator(const MeasurementPoints& points, const GBuffer& gbuffer,
                                           double initial_radius_pixels)
    : count_(points.size(), 0.0), radius2_(points.size()), flux_(points.size(), glm::dvec3(0.0)) {
  for (size_t i = 0; i < points.size(); ++i) {
    float radius = static_cast<float>(initial_radius_pixels) * gbuffer.footprint[points.pixel[i]];
    radius2_[i] = radius * radius;
  }
}

namespace {

float median_radius(const std::vector<float>& radius2) {
  std::vector<float> copy = radius2;
  std::nth_element(copy.begin(), copy.begin() + copy.size() / 2, copy.end());
  return std::sqrt(copy[copy.size() / 2]);
}

}  // namespace

void ProgressiveEstimator::gather(const MeasurementPoints& points, const std::vector<Photon>& photons, double alpha) {
  if (photons.empty() || points.size() == 0) return;
  PhotonGrid grid(photons, std::max(1e-7f, median_radius(radius2_)));
  parallel_blocks(points.size(), 512, [&](size_t begin, size_t end, size_t) {
    for (size_t i = begin; i < end; ++i) {
      const Vec3 point = points.position[i], normal = points.normal[i];
      const float radius2 = radius2_[i];
      uint64_t found = 0;
      glm::dvec3 flux(0.0);
      grid.for_each_near(point, std::sqrt(radius2), [&](const Photon& photon) {
        Vec3 offset = photon.position - point;
        // Same surface side as the camera sees it; the sphere test does the rest.
        if (glm::dot(offset, offset) >= radius2 || glm::dot(photon.normal, normal) < 0.7f) return;
        ++found;
        flux += glm::dvec3(photon.power);
      });
      if (found == 0) continue;
      double previous = count_[i];
      double kept = previous + alpha * static_cast<double>(found);
      double ratio = kept / (previous + static_cast<double>(found));
      count_[i] = kept;
      radius2_[i] = static_cast<float>(radius2 * ratio);
      flux_[i] = (flux_[i] + flux) * ratio;
    }
  });
}

glm::dvec3 ProgressiveEstimator::value(size_t point) const {
  double emitted = static_cast<double>(std::max<uint64_t>(1, emitted_));
  return flux_[point] / (kPiDouble * radius2_[point] * emitted);
}

double estimated_relative_mse(const std::vector<glm::dvec3>& value, const std::vector<glm::dvec3>& squared_error) {
  if (value.empty()) return 0.0;
  double mean = 0.0;
  for (const glm::dvec3& v : value) mean += (v.x + v.y + v.z) / 3.0;
  mean /= static_cast<double>(value.size());
  const double epsilon = relative_mse_epsilon(mean);
  double sum = 0.0;
  for (size_t i = 0; i < value.size(); ++i)
    for (int c = 0; c < 3; ++c) sum += squared_error[i][c] / (value[i][c] * value[i][c] + epsilon);
  return sum / (3.0 * static_cast<double>(value.size()));
}

void write_points(const MeasurementPoints& points, const std::vector<glm::dvec3>& values, bool root, Image& image) {
  for (size_t i = 0; i < points.size(); ++i) {
    glm::dvec3 v = root ? glm::sqrt(glm::max(values[i], glm::dvec3(0.0))) : values[i];
    image.set_rgb(points.pixel[i], Color(v));
  }
}

}  // namespace causticbench
