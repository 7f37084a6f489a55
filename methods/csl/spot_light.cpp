#include "methods/csl/spot_light.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace causticbench::csl {

double Profile::area_ratio(double r, double z) const {
  // sigma = |s s'| / r with s = r (1 - z g(r)): the 1/r cancels, so the limit at r = 0 needs no care.
  return std::fabs((1.0 - z * g(r)) * ds(r, z));
}

namespace {

// Positive roots of A r^2 + B r + C = 0 up to max_radius, appended with `side`. The product form
// q = -(B + sign(B) sqrt(B^2 - 4AC)) / 2, roots q / A and C / q, loses no digits when A is tiny
// (one root tends to -C / B, the other beyond any image) or when B^2 >> AC.
void positive_roots(double a, double b, double c, double max_radius, int side, Radii& radii) {
  auto keep = [&](double r) {
    if (!(r > 0.0 && r <= max_radius)) return;
    for (int i = 0; i < radii.count; ++i) {
      if (radii.side[i] == side && radii.radius[i] == r) return;  // a double root, once
    }
    if (radii.count < 3) {
      radii.radius[radii.count] = r;
      radii.side[radii.count] = side;
      ++radii.count;
    }
  };
  if (a == 0.0) {
    if (b != 0.0) keep(-c / b);
    return;
  }
  const double discriminant = b * b - 4.0 * a * c;
  if (discriminant < 0.0) return;
  const double q = -0.5 * (b + std::copysign(std::sqrt(discriminant), b));
  if (q == 0.0) {  // b = 0 and c = 0: the double root 0, which is not a positive radius
    return;
  }
  keep(q / a);
  keep(c / q);
}

}  // namespace

Radii Profile::radii(double z, double rho, double max_radius) const {
  // s(r) = -A r^2 - B r with A = z kappa beta, B = z kappa - 1; s(r) = +rho (case i) and -rho (case ii).
  const double a = z * kappa * beta, b = z * kappa - 1.0;
  Radii radii;
  positive_roots(a, b, rho, max_radius, +1, radii);
  positive_roots(a, b, -rho, max_radius, -1, radii);
  return radii;
}

IntensityImage::IntensityImage(int size, int channels, float half_size, const std::vector<float>& values,
                               Precision precision)
    : size_(size), channels_(channels), half_size_(half_size), precision_(precision) {
  if (size <= 0 || (channels != 1 && channels != 3) || !(half_size > 0.0f) ||
      values.size() != static_cast<size_t>(size) * size * channels) {
    throw std::invalid_argument("IntensityImage: inconsistent size, channels, half size or values");
  }
  if (precision == Precision::float32) {
    floats_ = values;
  } else {
    scales_.assign(channels, 0.0f);
    for (size_t i = 0; i < values.size(); ++i) scales_[i % channels] = std::max(scales_[i % channels], values[i]);
    for (float& scale : scales_) scale = scale > 0.0f ? scale / 65535.0f : 1.0f;
    quantised_.resize(values.size());
    for (size_t i = 0; i < values.size(); ++i) {
      const float q = std::round(std::max(0.0f, values[i]) / scales_[i % channels]);
      quantised_[i] = static_cast<uint16_t>(std::min(65535.0f, q));
    }
  }
  build_radial_table();
  find_support();
}

IntensityImage IntensityImage::from_stored(int size, int channels, float half_size, Precision precision,
                                           std::vector<float> floats, std::vector<uint16_t> quantised,
                                           std::vector<float> scales) {
  const size_t texels = size > 0 ? static_cast<size_t>(size) * size * channels : 0;
  const bool fits = size > 0 && (channels == 1 || channels == 3) && half_size > 0.0f &&
                    (precision == Precision::float32 ? floats.size() == texels && quantised.empty() && scales.empty()
                                                     : floats.empty() && quantised.size() == texels &&
                                                           scales.size() == static_cast<size_t>(channels));
  if (!fits) throw std::invalid_argument("IntensityImage: stored parts of the wrong size");
  IntensityImage image;
  image.size_ = size;
  image.channels_ = channels;
  image.half_size_ = half_size;
  image.precision_ = precision;
  image.floats_ = std::move(floats);
  image.quantised_ = std::move(quantised);
  image.scales_ = std::move(scales);
  image.build_radial_table();
  image.find_support();
  return image;
}

float IntensityImage::texel(int i, int j, int channel) const {
  const size_t index = (static_cast<size_t>(j) * size_ + i) * channels_ + channel;
  return precision_ == Precision::float32 ? floats_[index] : quantised_[index] * scales_[channel];
}

std::vector<float> IntensityImage::decoded() const {
  std::vector<float> values(static_cast<size_t>(size_) * size_ * channels_);
  for (int j = 0; j < size_; ++j) {
    for (int i = 0; i < size_; ++i) {
      for (int c = 0; c < channels_; ++c) values[(static_cast<size_t>(j) * size_ + i) * channels_ + c] = texel(i, j, c);
    }
  }
  return values;
}

void IntensityImage::lookup(float x, float y, float* out) const {
  for (int c = 0; c < channels_; ++c) out[c] = 0.0f;
  const float scale = size_ / (2.0f * half_size_);
  const float fx = (x + half_size_) * scale - 0.5f, fy = (y + half_size_) * scale - 0.5f;
  if (!(fx > -1.0f && fy > -1.0f && fx < size_ && fy < size_)) return;
  const int i0 = static_cast<int>(std::floor(fx)), j0 = static_cast<int>(std::floor(fy));
  const float tx = fx - i0, ty = fy - j0;
  const float weights[4] = {(1 - tx) * (1 - ty), tx * (1 - ty), (1 - tx) * ty, tx * ty};
  const int is[4] = {i0, i0 + 1, i0, i0 + 1}, js[4] = {j0, j0, j0 + 1, j0 + 1};
  for (int k = 0; k < 4; ++k) {
    if (is[k] < 0 || js[k] < 0 || is[k] >= size_ || js[k] >= size_) continue;
    for (int c = 0; c < channels_; ++c) out[c] += weights[k] * texel(is[k], js[k], c);
  }
}

void IntensityImage::build_radial_table() {
  // The ring integral J(r) = integral over theta of I(r, theta) r of the bilinear image, sampled at
  // bin edges with angles half a texel apart along the ring, and integrated over r assuming J linear
  // in each bin: exact for an image constant near the axis, where the on-axis disks are small.
  // It reads the decoded texels directly and walks each ring by a fixed rotation, not by lookup()
  // and sincos per sample: the table was half of a set's build time (perf, the bunny).
  radial_bins_ = 2 * size_;
  radial_.assign(static_cast<size_t>(radial_bins_ + 1) * channels_, 0.0);
  ring_.assign(static_cast<size_t>(radial_bins_ + 1) * channels_, 0.0);
  const std::vector<float> values = decoded();
  const double width = 2.0 * half_size_ / size_, bin_width = max_radius() / radial_bins_;
  const double scale = size_ / (2.0 * half_size_);
  double sum[3];
  for (int k = 0; k <= radial_bins_; ++k) {
    const double r = k * bin_width;
    const int angles = std::max(16, static_cast<int>(std::ceil(2.0 * kPiDouble * r / (0.5 * width))));
    const double step = 2.0 * kPiDouble / angles, cos_step = std::cos(step), sin_step = std::sin(step);
    double x = r * std::cos(0.5 * step), y = r * std::sin(0.5 * step);
    for (int c = 0; c < channels_; ++c) sum[c] = 0.0;
    for (int m = 0; m < angles; ++m) {
      // Bilinear, zero beyond the edge texels, as lookup() reads.
      const double fx = (x + half_size_) * scale - 0.5, fy = (y + half_size_) * scale - 0.5;
      if (fx > -1.0 && fy > -1.0 && fx < size_ && fy < size_) {
        const int i0 = static_cast<int>(std::floor(fx)), j0 = static_cast<int>(std::floor(fy));
        const double tx = fx - i0, ty = fy - j0;
        const double weights[4] = {(1 - tx) * (1 - ty), tx * (1 - ty), (1 - tx) * ty, tx * ty};
        const int is[4] = {i0, i0 + 1, i0, i0 + 1}, js[4] = {j0, j0, j0 + 1, j0 + 1};
        for (int t = 0; t < 4; ++t) {
          if (is[t] < 0 || js[t] < 0 || is[t] >= size_ || js[t] >= size_) continue;
          const float* texel = &values[(static_cast<size_t>(js[t]) * size_ + is[t]) * channels_];
          for (int c = 0; c < channels_; ++c) sum[c] += weights[t] * texel[c];
        }
      }
      const double turned = x * cos_step - y * sin_step;
      y = x * sin_step + y * cos_step;
      x = turned;
    }
    for (int c = 0; c < channels_; ++c) ring_[static_cast<size_t>(k) * channels_ + c] = sum[c] * r * step;
  }
  for (int k = 0; k < radial_bins_; ++k) {
    for (int c = 0; c < channels_; ++c) {
      const size_t here = static_cast<size_t>(k) * channels_ + c, next = here + channels_;
      radial_[next] = radial_[here] + 0.5 * (ring_[here] + ring_[next]) * bin_width;
    }
  }
}

void IntensityImage::find_support() {
  const double width = 2.0 * half_size_ / size_;
  double farthest = -1.0;
  for (int j = 0; j < size_; ++j) {
    for (int i = 0; i < size_; ++i) {
      bool zero = true;
      for (int c = 0; c < channels_; ++c) zero = zero && texel(i, j, c) == 0.0f;
      if (zero) continue;
      const double x = -half_size_ + (i + 0.5) * width, y = -half_size_ + (j + 0.5) * width;
      farthest = std::max(farthest, std::sqrt(x * x + y * y));
    }
  }
  // A lookup reads a texel when it is less than one texel from its centre along each axis.
  support_radius_ = farthest < 0.0 ? 0.0 : farthest + 2.0 * 1.41421356237 * width;
}

void IntensityImage::flux_within(double r, double* out) const {
  const double bin_width = max_radius() / radial_bins_;
  const double position = std::clamp(r / bin_width, 0.0, static_cast<double>(radial_bins_));
  const int k = std::min(radial_bins_ - 1, static_cast<int>(position));
  const double t = (position - k) * bin_width;
  for (int c = 0; c < channels_; ++c) {
    const size_t here = static_cast<size_t>(k) * channels_ + c, next = here + channels_;
    // J linear over the bin: C(r_k + t) = C_k + J_k t + (J_k+1 - J_k) t^2 / (2 bin).
    out[c] = radial_[here] + ring_[here] * t + 0.5 * (ring_[next] - ring_[here]) * t * t / bin_width;
  }
}

void IntensityImage::total_flux(double* out) const {
  const double area = std::pow(2.0 * half_size_ / size_, 2);
  for (int c = 0; c < channels_; ++c) out[c] = 0.0;
  for (int j = 0; j < size_; ++j) {
    for (int i = 0; i < size_; ++i) {
      for (int c = 0; c < channels_; ++c) out[c] += texel(i, j, c) * area;
    }
  }
}

size_t IntensityImage::memory_bytes() const {
  return floats_.size() * sizeof(float) + quantised_.size() * sizeof(uint16_t) + scales_.size() * sizeof(float) +
         (radial_.size() + ring_.size()) * sizeof(double);
}

void set_plane_axes(SpotGeometry& light) { orthonormal_basis(light.axis, light.u, light.v); }

Vec3 SpotGeometry::ray_direction(double x, double y) const {
  const double r = std::sqrt(x * x + y * y);
  const double g = profile.g(r);
  const glm::dvec3 direction = glm::dvec3(axis) - g * (x * glm::dvec3(u) + y * glm::dvec3(v));
  return Vec3(glm::normalize(direction));
}

}  // namespace causticbench::csl
