#include "methods/csl/splat.h"

#include <algorithm>
#include <cmath>

#include <nanoflann.hpp>

namespace causticbench::csl {

int automatic_image_size(double half, double delta) {
  for (int size : {128, 256, 512}) {
    if (2.0 * half / size <= 0.5 * delta) return size;
  }
  return 512;
}

namespace {
struct OnPlane {
  double x, y;
  double along;  // d . a
  double delta;  // this ray's splat radius
};

// nanoflann's view of the rays' points on the light plane.
struct PlaneCloud {
  const std::vector<OnPlane>* points = nullptr;
  size_t kdtree_get_point_count() const { return points->size(); }
  double kdtree_get_pt(size_t index, size_t dimension) const {
    return dimension == 0 ? (*points)[index].x : (*points)[index].y;
  }
  template <class Box>
  bool kdtree_get_bbox(Box&) const { return false; }
};
using PlaneTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, PlaneCloud>, PlaneCloud, 2>;

// Each point's delta: splat_scale times the larger of the object spacing and its mean distance to
// its four nearest neighbours, at most ten times the former.
void set_deltas(std::vector<OnPlane>& points, const SplatSettings& settings) {
  const double floor = settings.splat_scale * settings.spacing;
  for (OnPlane& point : points) point.delta = floor;
  if (points.size() < 2) return;
  PlaneCloud cloud{&points};
  PlaneTree tree(2, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16));
  tree.buildIndex();
  const size_t wanted = std::min<size_t>(5, points.size());
  std::vector<uint32_t> indices(wanted);
  std::vector<double> squared(wanted);
  for (OnPlane& point : points) {
    const double query[2] = {point.x, point.y};
    const size_t found = tree.knnSearch(query, wanted, indices.data(), squared.data());
    double sum = 0.0;
    int count = 0;
    for (size_t k = 0; k < found; ++k) {
      if (squared[k] <= 0.0) continue;  // itself (or a ray at the same point)
      sum += std::sqrt(squared[k]);
      ++count;
    }
    // At most ten times the paper's delta: an isolated ray far out would otherwise be spread over
    // the whole image.
    if (count > 0) point.delta = std::clamp(settings.splat_scale * sum / count, floor, 10.0 * floor);
  }
}
// Below this cosine to the axis a ray's splat would be stretched beyond use; it is taken at this one.
constexpr double kSmallestCosine = 0.1;
}  // namespace

IntensityImage splat_intensity(const std::vector<CausticRay>& rays, const std::vector<uint32_t>& members,
                               const SpotLight& light, const SplatSettings& settings) {
  const glm::dvec3 c(light.origin), a(light.axis), u(light.u), v(light.v);
  std::vector<OnPlane> points;
  points.reserve(members.size());
  double half = 0.0;
  for (uint32_t index : members) {
    const CausticRay& ray = rays[index];
    const glm::dvec3 q(ray.origin), d(ray.direction);
    const double along = std::max(kSmallestCosine, glm::dot(d, a));
    const glm::dvec3 p = q + (glm::dot(c - q, a) / glm::dot(d, a)) * d;
    points.push_back(OnPlane{glm::dot(p - c, u), glm::dot(p - c, v), along, 0.0});
  }
  set_deltas(points, settings);
  std::vector<double> deltas;
  for (const OnPlane& point : points) {
    half = std::max(half, std::max(std::fabs(point.x), std::fabs(point.y)) + 2.0 * point.delta / point.along);
    deltas.push_back(point.delta);
  }
  double median = settings.splat_scale * settings.spacing;
  if (!deltas.empty()) {
    std::nth_element(deltas.begin(), deltas.begin() + deltas.size() / 2, deltas.end());
    median = deltas[deltas.size() / 2];
  }
  half = std::max(half, 2.0 * median);
  if (!(half > 0.0)) half = 1e-6;
  const int size = settings.image_size > 0 ? settings.image_size : automatic_image_size(half, median);
  const int channels = settings.channels;
  const double width = 2.0 * half / size;
  std::vector<float> values(static_cast<size_t>(size) * size * channels, 0.0f);
  std::vector<double> weights;
  for (size_t k = 0; k < points.size(); ++k) {
    const OnPlane& point = points[k];
    const CausticRay& ray = rays[members[k]];
    // The ellipse's axes as Gaussian standard deviations (the ellipse at two of them), along the
    // radial direction and across it, plus the texel's reconstruction variance.
    const double radius = std::sqrt(point.x * point.x + point.y * point.y);
    const double cx = radius > 0.0 ? point.x / radius : 1.0, cy = radius > 0.0 ? point.y / radius : 0.0;
    const double radial = 0.5 * point.delta / point.along, across = 0.5 * point.delta;
    const double texel_variance = 0.25 * width * width;
    const double vr = radial * radial + texel_variance, va = across * across + texel_variance;
    // Covariance R diag(vr, va) R^T, R = [[cx, -cy], [cy, cx]]; and its inverse.
    const double sxx = cx * cx * vr + cy * cy * va, syy = cy * cy * vr + cx * cx * va, sxy = cx * cy * (vr - va);
    const double determinant = sxx * syy - sxy * sxy;
    const double ixx = syy / determinant, iyy = sxx / determinant, ixy = -sxy / determinant;
    const double reach = 3.0 * std::sqrt(std::max(vr, va));
    const int i0 = std::max(0, static_cast<int>(std::floor((point.x - reach + half) / width)));
    const int i1 = std::min(size - 1, static_cast<int>(std::floor((point.x + reach + half) / width)));
    const int j0 = std::max(0, static_cast<int>(std::floor((point.y - reach + half) / width)));
    const int j1 = std::min(size - 1, static_cast<int>(std::floor((point.y + reach + half) / width)));
    if (i1 < i0 || j1 < j0) continue;
    weights.assign(static_cast<size_t>(i1 - i0 + 1) * (j1 - j0 + 1), 0.0);
    double total = 0.0;
    for (int j = j0; j <= j1; ++j) {
      for (int i = i0; i <= i1; ++i) {
        const double dx = -half + (i + 0.5) * width - point.x, dy = -half + (j + 0.5) * width - point.y;
        const double w = std::exp(-0.5 * (ixx * dx * dx + 2.0 * ixy * dx * dy + iyy * dy * dy));
        weights[static_cast<size_t>(j - j0) * (i1 - i0 + 1) + (i - i0)] = w;
        total += w;
      }
    }
    if (!(total > 0.0)) continue;
    const double area = width * width;
    const float energy[3] = {channels == 1 ? ray.weight : ray.energy.r, ray.energy.g, ray.energy.b};
    for (int j = j0; j <= j1; ++j) {
      for (int i = i0; i <= i1; ++i) {
        const double w = weights[static_cast<size_t>(j - j0) * (i1 - i0 + 1) + (i - i0)] / (total * area);
        float* texel = &values[(static_cast<size_t>(j) * size + i) * channels];
        for (int ch = 0; ch < channels; ++ch) texel[ch] += static_cast<float>(energy[ch] * w);
      }
    }
  }
  return IntensityImage(size, channels, static_cast<float>(half), values, settings.precision);
}

}  // namespace causticbench::csl
