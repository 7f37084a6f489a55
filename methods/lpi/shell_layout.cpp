#include "methods/lpi/shell_layout.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace causticbench::lpi {

namespace {

// integral over [r0, r1] of (a + b r) r^2 dr: Simpson's rule, exact for this cubic.
double cubic_integral(double r0, double r1, double value0, double value1) {
  auto f = [&](double r) {
    const double h = r1 > r0 ? (r - r0) / (r1 - r0) : 0.0;
    return (value0 + (value1 - value0) * h) * r * r;
  };
  return (r1 - r0) / 6.0 * (f(r0) + 4.0 * f(0.5 * (r0 + r1)) + f(r1));
}

}  // namespace

ShellLayout::ShellLayout(Vec3 center, float radius, int shell_count, int subdivision, ShellSpacing spacing)
    : VolumeLayout(center, radius), mesh_(SphericalMesh::geodesic_vertices(subdivision)) {
  if (shell_count < 1) throw std::invalid_argument("ShellLayout: no shell");
  for (int k = 0; k < shell_count; ++k) {
    const double fraction = static_cast<double>(k + 1) / shell_count;
    radii_.push_back(static_cast<float>(radius * (spacing == ShellSpacing::uniform ? fraction : fraction * fraction)));
  }
  radii_.back() = radius;
  const auto& points = mesh_.points();
  const auto& triangles = mesh_.triangles();
  // Angular integrals of the vertex basis functions: a midpoint rule over the face's chord triangle,
  // with dw = h / |y|^3 dA, scaled so that each face's three integrals sum to its exact solid angle
  // (the basis functions sum to one, so the integrals must sum to 4 pi).
  angular_integral_.assign(points.size(), 0.0);
  const int parts = 8;
  for (const auto& triangle : triangles) {
    const glm::dvec3 a(points[triangle[0]]), b(points[triangle[1]]), c(points[triangle[2]]);
    const glm::dvec3 normal = glm::normalize(glm::cross(b - a, c - a));
    const double height = glm::dot(normal, a);
    double sums[3] = {0.0, 0.0, 0.0};
    for (int i = 0; i < parts; ++i) {
      for (int j = 0; j < parts - i; ++j) {
        // Upward and downward sub-triangles; their centroids in barycentric coordinates.
        for (int flip = 0; flip < (j < parts - i - 1 ? 2 : 1); ++flip) {
          double u = (i + (flip ? 2.0 : 1.0) / 3.0) / parts, v = (j + (flip ? 2.0 : 1.0) / 3.0) / parts;
          double weights[3] = {1.0 - u - v, u, v};
          glm::dvec3 y = weights[0] * a + weights[1] * b + weights[2] * c;
          double jacobian = height / std::pow(glm::length(y), 3.0);
          for (int corner = 0; corner < 3; ++corner) sums[corner] += weights[corner] * jacobian;
        }
      }
    }
    const double exact = solid_angle(a, b, c), total = sums[0] + sums[1] + sums[2];
    for (int corner = 0; corner < 3; ++corner) angular_integral_[triangle[corner]] += sums[corner] * exact / total;
  }
  // Radial integrals: shell 0's hat is one from the centre to r_0 (the innermost shell also serves the core).
  radial_integral_.assign(radii_.size(), 0.0);
  for (size_t k = 0; k < radii_.size(); ++k) {
    const double lower = k == 0 ? 0.0 : radii_[k - 1];
    radial_integral_[k] += cubic_integral(lower, radii_[k], k == 0 ? 1.0 : 0.0, 1.0);
    if (k + 1 < radii_.size()) radial_integral_[k] += cubic_integral(radii_[k], radii_[k + 1], 1.0, 0.0);
  }
}

int ShellLayout::radial_interval(float r) const {
  return static_cast<int>(std::upper_bound(radii_.begin(), radii_.end(), r) - radii_.begin());
}

void ShellLayout::add_piece(const PathSegment& segment, const Vec3& offset_origin, float t0, float t1,
                            uint32_t triangle, Orientation orientation, float* sums) const {
  const int channels = channel_count(orientation);
  const auto& corners = mesh_.triangles()[triangle];
  const auto& points = mesh_.points();
  const int interval = radial_interval(glm::length(offset_origin + segment.direction * (0.5f * (t0 + t1))));
  if (interval >= static_cast<int>(radii_.size())) return;
  const float half = 0.5f * (t1 - t0), middle = 0.5f * (t0 + t1);
  const float gauss = half * 0.57735026919f;  // 1 / sqrt(3)
  for (float t : {middle - gauss, middle + gauss}) {
    const Vec3 x = offset_origin + segment.direction * t;
    float angular[3], total = 0.0f;
    for (int corner = 0; corner < 3; ++corner) {
      angular[corner] = std::max(0.0f, glm::dot(mesh_.edge_normals()[triangle][corner], x));
      total += angular[corner];
    }
    if (!(total > 0.0f)) continue;
    float radial_upper = 1.0f;
    if (interval > 0) {
      const float lower = radii_[interval - 1], upper = radii_[interval];
      radial_upper = std::clamp((glm::length(x) - lower) / (upper - lower), 0.0f, 1.0f);
    }
    for (int corner = 0; corner < 3; ++corner) {
      const float weight = half * angular[corner] / total;
      const size_t vertex = corners[corner];
      add_track(segment, weight * radial_upper, points[vertex], orientation,
                sums + (interval * directions() + vertex) * channels);
      if (interval > 0) {
        add_track(segment, weight * (1.0f - radial_upper), points[vertex], orientation,
                  sums + ((interval - 1) * directions() + vertex) * channels);
      }
    }
  }
}

void ShellLayout::deposit(const PathSegment& segment, Orientation orientation, float* sums) const {
  float t_begin, t_end;
  if (!clip_to_ball(segment, center_, radius_, t_begin, t_end)) return;
  const Vec3 origin = segment.origin - center_;
  // Where the track crosses a shell sphere: the radial breakpoints.
  std::vector<float>& breaks = *[] {
    thread_local std::vector<float> storage;
    return &storage;
  }();
  breaks.clear();
  const float half_b = glm::dot(origin, segment.direction), origin_squared = glm::dot(origin, origin);
  for (float r : radii_) {
    const float discriminant = half_b * half_b - (origin_squared - r * r);
    if (!(discriminant > 0.0f)) continue;
    const float root = std::sqrt(discriminant);
    for (float t : {-half_b - root, -half_b + root}) {
      if (t > t_begin && t < t_end) breaks.push_back(t);
    }
  }
  breaks.push_back(t_end);
  std::sort(breaks.begin(), breaks.end());
  auto direction_at = [&](float t) { return glm::normalize(origin + segment.direction * t); };
  const float nudge = 1e-4f * (t_end - t_begin);
  uint32_t triangle = mesh_.locate(direction_at(t_begin + nudge)).triangle;
  size_t next_break = 0;
  float t = t_begin;
  // Each step ends at a shell or a face edge; a step that finds the point outside its face (rounding
  // at an edge, or the track passing through the centre) relocates instead. The bound stops a walk
  // that could not advance.
  for (int step = 0; step < 100000 && t < t_end; ++step) {
    float t_edge = t_end + 1.0f;
    int exit_corner = -1;
    for (int corner = 0; corner < 3; ++corner) {
      const Vec3& normal = mesh_.edge_normals()[triangle][corner];
      const float rate = glm::dot(normal, segment.direction);
      if (rate >= 0.0f) continue;
      const float crossing = -glm::dot(normal, origin) / rate;
      if (crossing > t && crossing < t_edge) {
        t_edge = crossing;
        exit_corner = corner;
      }
    }
    const float piece_end = std::min(breaks[next_break], t_edge);
    const Vec3 middle = origin + segment.direction * (0.5f * (t + piece_end));
    const float scale = glm::length(middle) * 1e-5f;
    bool inside = true;
    for (int corner = 0; corner < 3; ++corner) {
      inside = inside && glm::dot(mesh_.edge_normals()[triangle][corner], middle) >= -scale;
    }
    if (!inside) {
      const uint32_t located = mesh_.locate(glm::normalize(middle)).triangle;
      if (located != triangle) {
        triangle = located;
        continue;
      }
    }
    if (piece_end > t) add_piece(segment, origin, t, piece_end, triangle, orientation, sums);
    t = piece_end;
    if (breaks[next_break] <= piece_end && next_break + 1 < breaks.size()) ++next_break;
    if (exit_corner >= 0 && t_edge <= piece_end) triangle = mesh_.neighbours()[triangle][exit_corner];
  }
}

void ShellLayout::normalise(double photons_emitted, Orientation orientation, double* values) const {
  const int channels = channel_count(orientation);
  for (size_t k = 0; k < radii_.size(); ++k) {
    for (size_t v = 0; v < directions(); ++v) {
      const double factor = 1.0 / (angular_integral_[v] * radial_integral_[k] * photons_emitted);
      double* point = values + (k * directions() + v) * channels;
      for (int c = 0; c < channels; ++c) point[c] *= factor;
    }
  }
}

Stencil ShellLayout::stencil(const Vec3& position) const {
  Stencil stencil;
  const Vec3 offset = position - center_;
  const float r = glm::length(offset);
  const Vec3 direction = r > 0.0f ? offset / r : Vec3(0.0f, 1.0f, 0.0f);
  const SphericalMesh::Location location = mesh_.locate(direction);
  const auto& corners = mesh_.triangles()[location.triangle];
  int interval = std::min(radial_interval(r), static_cast<int>(radii_.size()));
  float radial_upper = 1.0f;
  if (interval == static_cast<int>(radii_.size())) {
    interval = static_cast<int>(radii_.size()) - 1;  // on the outer shell (or beyond, clamped)
  } else if (interval > 0) {
    const float lower = radii_[interval - 1], upper = radii_[interval];
    radial_upper = std::clamp((r - lower) / (upper - lower), 0.0f, 1.0f);
  }
  for (int corner = 0; corner < 3; ++corner) {
    stencil.points[stencil.count] = static_cast<uint32_t>(interval * directions() + corners[corner]);
    stencil.weights[stencil.count++] = location.weights[corner] * radial_upper;
    if (interval > 0 && radial_upper < 1.0f) {
      stencil.points[stencil.count] = static_cast<uint32_t>((interval - 1) * directions() + corners[corner]);
      stencil.weights[stencil.count++] = location.weights[corner] * (1.0f - radial_upper);
    }
  }
  return stencil;
}

size_t ShellLayout::memory_bytes() const {
  return mesh_.memory_bytes() + radii_.size() * sizeof(float) +
         (angular_integral_.size() + radial_integral_.size()) * sizeof(double);
}

}  // namespace causticbench::lpi
