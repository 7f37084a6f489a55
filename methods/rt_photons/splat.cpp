#include "methods/rt_photons/splat.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/parallel.h"

namespace causticbench::rt_photons {

Footprint footprint_kind(const std::string& name) {
  if (name == "ray_differentials") return Footprint::ray_differentials;
  if (name == "ray_cone") return Footprint::ray_cone;
  if (name == "fixed") return Footprint::fixed;
  throw std::invalid_argument("rt_photons: unknown footprint '" + name + "'");
}

namespace {

constexpr int kTile = 32;
constexpr float kNormalCosine = 0.9063f;  // cos 25 degrees

// A photon's kernel: r^2 = (d . e1)^2 / a^2 + (d . e2)^2 / b^2 for d the offset in the tangent plane,
// weight (1 - r^2)^2 inside r < 1; its pixel bounds; its normaliser sum over the points that count of
// weight x area.
struct Kernel {
  Vec3 e1{0.0f}, e2{0.0f};
  float inverse_a2 = 0.0f, inverse_b2 = 0.0f;
  int x0 = 0, y0 = 0, x1 = -1, y1 = -1;  // inclusive pixel bounds
  double normaliser = 0.0;
};

// The kernel's r^2 at G-buffer pixel `pixel` for photon `photon` (the point inside the kernel where it is
// below 1), or -1 where the point is not on the photon's surface (not a receiver, off its plane by more than
// a pixel's footprint and a half, or turned more than 25 degrees from its normal).
float surface_radius2(const LandedPhoton& photon, const Kernel& kernel, const GBuffer& gbuffer, size_t pixel) {
  if (!gbuffer.receiver[pixel]) return -1.0f;
  const Vec3 offset = gbuffer.position[pixel] - photon.position;
  const float plane = glm::dot(offset, photon.normal);
  if (std::abs(plane) > 1.5f * gbuffer.footprint[pixel]) return -1.0f;
  if (glm::dot(gbuffer.normal[pixel], photon.normal) < kNormalCosine) return -1.0f;
  const float s = glm::dot(offset, kernel.e1), t = glm::dot(offset, kernel.e2);
  return s * s * kernel.inverse_a2 + t * t * kernel.inverse_b2;
}

// The ellipse of the covariance a_u a_u^T + a_v a_v^T in the tangent plane (its axes e1, e2 and radii),
// each radius clamped to [min, max] pixels of `pixel_size` (scene units a pixel there).
float shape_kernel(const LandedPhoton& photon, const SplatSettings& settings, float pixel_size, Kernel& kernel,
                   SplatCounts& counts) {
  Vec3 t1, t2;
  orthonormal_basis(photon.normal, t1, t2);
  float radius1 = 0.0f, radius2 = 0.0f;
  if (settings.footprint == Footprint::ray_differentials) {
    const glm::vec2 a(glm::dot(photon.axis_u, t1), glm::dot(photon.axis_u, t2));
    const glm::vec2 b(glm::dot(photon.axis_v, t1), glm::dot(photon.axis_v, t2));
    const float c11 = a.x * a.x + b.x * b.x, c12 = a.x * a.y + b.x * b.y, c22 = a.y * a.y + b.y * b.y;
    const float mean = 0.5f * (c11 + c22), spread = std::sqrt(std::max(0.0f, 0.25f * (c11 - c22) * (c11 - c22) + c12 * c12));
    const float l1 = mean + spread, l2 = std::max(0.0f, mean - spread);
    glm::vec2 axis = std::abs(c12) > 1e-30f ? glm::vec2(l1 - c22, c12) : (c11 >= c22 ? glm::vec2(1, 0) : glm::vec2(0, 1));
    axis = glm::normalize(axis);
    kernel.e1 = axis.x * t1 + axis.y * t2;
    kernel.e2 = -axis.y * t1 + axis.x * t2;
    radius1 = std::sqrt(l1), radius2 = std::sqrt(l2);
  } else {
    kernel.e1 = t1, kernel.e2 = t2;
    radius1 = radius2 = settings.footprint == Footprint::ray_cone ? photon.cone_width : settings.fixed_pixels * pixel_size;
  }
  const float unclamped = std::sqrt(radius1 * radius2) / pixel_size;
  const float low = settings.min_pixels * pixel_size, high = settings.max_pixels * pixel_size;
  if (!(radius2 >= low) || !(radius1 >= low)) ++counts.clamped_small;
  if (!(radius1 <= high)) ++counts.clamped_large;
  radius1 = std::clamp(std::isfinite(radius1) ? radius1 : high, low, high);
  radius2 = std::clamp(std::isfinite(radius2) ? radius2 : high, low, high);
  kernel.inverse_a2 = 1.0f / (radius1 * radius1);
  kernel.inverse_b2 = 1.0f / (radius2 * radius2);
  return unclamped;
}

// The camera's rays through the pixels' centres and the distance along each to the point its pixel sees
// (0 for the background): what the occlusion test reads for every pixel a kernel's bounds hold that is
// not on the photon's surface, computed once per frame.
struct PixelRays {
  std::vector<Ray> ray;
  std::vector<float> distance;
};

PixelRays pixel_rays(const CameraFrame& camera, const GBuffer& gbuffer) {
  PixelRays rays;
  rays.ray.resize(static_cast<size_t>(gbuffer.width) * gbuffer.height);
  rays.distance.resize(rays.ray.size(), 0.0f);
  parallel_blocks(static_cast<size_t>(gbuffer.height), 16, [&](size_t begin, size_t end, size_t) {
    for (size_t y = begin; y < end; ++y)
      for (int x = 0; x < gbuffer.width; ++x) {
        const size_t pixel = y * gbuffer.width + x;
        rays.ray[pixel] = camera.primary_ray(x, static_cast<int>(y));
        if (gbuffer.object[pixel] >= 0) rays.distance[pixel] = glm::length(gbuffer.position[pixel] - rays.ray[pixel].origin);
      }
  });
  return rays;
}

// The kernel's weight times area at the point where `ray` (a pixel's camera ray) meets the photon's plane,
// the area the pixel's footprint there (as core/gbuffer.cpp computes it); 0 where the ray does not meet it
// or meets it no farther than `nearer_than` (behind the eye by default).
double virtual_share(const LandedPhoton& photon, const Kernel& kernel, const CameraFrame& camera, const Vec3& view_axis,
                     const Ray& ray, float nearer_than = 0.0f) {
  const float facing = glm::dot(ray.direction, photon.normal);
  if (std::abs(facing) < 1e-6f) return 0.0;
  const float t = glm::dot(photon.position - ray.origin, photon.normal) / facing;
  if (!(t > nearer_than)) return 0.0;
  const Vec3 offset = ray.origin + t * ray.direction - photon.position;
  const float s = glm::dot(offset, kernel.e1), u = glm::dot(offset, kernel.e2);
  const float r2 = s * s * kernel.inverse_a2 + u * u * kernel.inverse_b2;
  if (r2 >= 1.0f) return 0.0;
  const float along_view = t * std::abs(glm::dot(ray.direction, view_axis));
  const float side = camera.pixel_footprint(along_view) / std::sqrt(std::max(0.05f, std::abs(facing)));
  return double((1.0f - r2) * (1.0f - r2)) * side * side;
}

// Over the pixels of [x0, x1] x [y0, y1] outside the image.
double outside_share(const LandedPhoton& photon, const Kernel& kernel, const CameraFrame& camera, const Vec3& view_axis,
                     int width, int height, int x0, int y0, int x1, int y1) {
  double share = 0.0;
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x)
      if (x < 0 || x >= width || y < 0 || y >= height)
        share += virtual_share(photon, kernel, camera, view_axis, camera.primary_ray(x, y));
  return share;
}

}  // namespace

Image splat_photons(const std::vector<LandedPhoton>& photons, const CameraFrame& camera, const GBuffer& gbuffer,
                    const SplatSettings& settings, SplatCounts& counts, std::vector<float>* footprint_pixels) {
  const int width = gbuffer.width, height = gbuffer.height;
  Image result(width, height, 3);
  std::vector<Kernel> kernels(photons.size());
  std::vector<float> unclamped(photons.size(), 0.0f);
  const Vec3 view_axis = camera.primary_ray(width / 2, height / 2).direction;  // as core/gbuffer.cpp
  const PixelRays rays = pixel_rays(camera, gbuffer);
  std::vector<SplatCounts> block_counts((photons.size() + 4095) / 4096);
  // Per photon: the kernel, its bounds and its normaliser.
  parallel_blocks(photons.size(), 4096, [&](size_t begin, size_t end, size_t block) {
    SplatCounts& local = block_counts[block];
    for (size_t p = begin; p < end; ++p) {
      const LandedPhoton& photon = photons[p];
      Kernel& kernel = kernels[p];
      const std::optional<CameraFrame::ImagePoint> seen = camera.project(photon.position, photon.normal);
      const std::optional<glm::dvec2> centre = camera.image_position(photon.position);
      if (!centre) {
        ++local.hidden, local.hidden_flux += luminance(photon.power);
        continue;
      }
      // Scene units a pixel at the hit: the side of a pixel's area on the surface there.
      const float pixel_size = seen && seen->pixels_per_area > 0.0 ? static_cast<float>(1.0 / std::sqrt(seen->pixels_per_area))
                                                                    : 0.0f;
      float size = pixel_size;
      if (!(size > 0.0f)) {
        // Outside the image: a pixel's size at its depth from the nearest pixel of the image.
        const int x = std::clamp(static_cast<int>(centre->x), 0, width - 1), y = std::clamp(static_cast<int>(centre->y), 0, height - 1);
        size = gbuffer.footprint[static_cast<size_t>(y) * width + x];
        if (!(size > 0.0f)) size = camera.pixel_footprint(glm::length(photon.position - camera.position()));
      }
      unclamped[p] = shape_kernel(photon, settings, size, kernel, local);
      const float radius = 1.0f / std::sqrt(std::min(kernel.inverse_a2, kernel.inverse_b2));
      // Pixel bounds: the images of the four points along the axes at the larger radius, a pixel wider.
      double lower_x = centre->x, upper_x = centre->x, lower_y = centre->y, upper_y = centre->y;
      for (const Vec3& reach : {radius * kernel.e1, -radius * kernel.e1, radius * kernel.e2, -radius * kernel.e2}) {
        const std::optional<glm::dvec2> at = camera.image_position(photon.position + reach);
        if (!at) continue;
        lower_x = std::min(lower_x, at->x), upper_x = std::max(upper_x, at->x);
        lower_y = std::min(lower_y, at->y), upper_y = std::max(upper_y, at->y);
      }
      const int x0 = static_cast<int>(std::floor(lower_x)) - 1, x1 = static_cast<int>(std::floor(upper_x)) + 1;
      const int y0 = static_cast<int>(std::floor(lower_y)) - 1, y1 = static_cast<int>(std::floor(upper_y)) + 1;
      // A kernel larger than the image is one that a clamp could not bound (a photon at the eye's plane).
      if (static_cast<double>(x1 - x0 + 1) * (y1 - y0 + 1) > 16.0 * width * height) {
        ++local.hidden, local.hidden_flux += luminance(photon.power);
        unclamped[p] = 0.0f;
        continue;
      }
      kernel.x0 = std::max(0, x0), kernel.y0 = std::max(0, y0);
      kernel.x1 = std::min(width - 1, x1), kernel.y1 = std::min(height - 1, y1);
      // The kernel's share on points of its surface some pixel sees, and on those it would see but for an
      // occluder in front (a pixel whose point lies nearer than the photon's plane along its ray) or the
      // image's edge: taken on the photon's plane, they count in the normaliser and get nothing, so that
      // a photon partly hidden puts in view only the share that lands in view. Where the surface itself
      // ends (the point behind the plane, the receivers' edge, the background) the kernel is cut and the
      // seen share takes the whole flux.
      double in_view = 0.0, unseen = 0.0;
      for (int y = kernel.y0; y <= kernel.y1; ++y)
        for (int x = kernel.x0; x <= kernel.x1; ++x) {
          const size_t pixel = static_cast<size_t>(y) * width + x;
          const float r2 = surface_radius2(photon, kernel, gbuffer, pixel);
          if (r2 >= 0.0f) {
            // On the photon's surface: inside the kernel it counts, outside it the plane's point is as far.
            if (r2 < 1.0f) in_view += double((1.0f - r2) * (1.0f - r2)) * gbuffer.footprint[pixel] * gbuffer.footprint[pixel];
          } else if (gbuffer.object[pixel] >= 0) {
            // An occluder: the pixel sees a point nearer than the photon's plane along its ray.
            unseen += virtual_share(photon, kernel, camera, view_axis, rays.ray[pixel],
                                    rays.distance[pixel] + 2.0f * gbuffer.footprint[pixel]);
          }
        }
      if (in_view > 0.0 && (x0 < 0 || y0 < 0 || x1 >= width || y1 >= height))
        unseen += outside_share(photon, kernel, camera, view_axis, width, height, x0, y0, x1, y1);
      kernel.normaliser = in_view > 0.0 ? in_view + unseen : 0.0;
      if (kernel.normaliser > 0.0) {
        ++local.splatted, local.splatted_flux += luminance(photon.power);
      } else {
        ++local.hidden, local.hidden_flux += luminance(photon.power);
        kernel.x1 = kernel.x0 - 1;
        unclamped[p] = 0.0f;
      }
    }
  });
  // The photons binned by tile, in photon order (a counting sort): each tile then adds its photons in the
  // same order whatever the thread count.
  const int tiles_x = (width + kTile - 1) / kTile, tiles_y = (height + kTile - 1) / kTile;
  std::vector<uint32_t> first(static_cast<size_t>(tiles_x) * tiles_y + 1, 0);
  auto for_tiles = [&](const Kernel& kernel, auto&& visit) {
    if (kernel.x1 < kernel.x0 || kernel.y1 < kernel.y0) return;
    for (int ty = kernel.y0 / kTile; ty <= kernel.y1 / kTile; ++ty)
      for (int tx = kernel.x0 / kTile; tx <= kernel.x1 / kTile; ++tx) visit(static_cast<size_t>(ty) * tiles_x + tx);
  };
  for (const Kernel& kernel : kernels) for_tiles(kernel, [&](size_t tile) { ++first[tile + 1]; });
  for (size_t tile = 1; tile < first.size(); ++tile) first[tile] += first[tile - 1];
  std::vector<uint32_t> binned(first.back());
  {
    std::vector<uint32_t> next(first.begin(), first.end() - 1);
    for (size_t p = 0; p < kernels.size(); ++p)
      for_tiles(kernels[p], [&](size_t tile) { binned[next[tile]++] = static_cast<uint32_t>(p); });
  }
  std::vector<uint64_t> tile_pixels(first.size() - 1, 0);
  parallel_blocks(first.size() - 1, 1, [&](size_t begin, size_t end, size_t) {
    for (size_t tile = begin; tile < end; ++tile) {
      const int tx0 = static_cast<int>(tile % tiles_x) * kTile, ty0 = static_cast<int>(tile / tiles_x) * kTile;
      for (uint32_t k = first[tile]; k < first[tile + 1]; ++k) {
        const LandedPhoton& photon = photons[binned[k]];
        const Kernel& kernel = kernels[binned[k]];
        const int x0 = std::max(kernel.x0, tx0), x1 = std::min(kernel.x1, tx0 + kTile - 1);
        const int y0 = std::max(kernel.y0, ty0), y1 = std::min(kernel.y1, ty0 + kTile - 1);
        for (int y = y0; y <= y1; ++y)
          for (int x = x0; x <= x1; ++x) {
            const size_t pixel = static_cast<size_t>(y) * width + x;
            const float r2 = surface_radius2(photon, kernel, gbuffer, pixel);
            if (!(r2 >= 0.0f && r2 < 1.0f)) continue;
            const float w = (1.0f - r2) * (1.0f - r2);
            const float scale = static_cast<float>(double(w) / kernel.normaliser);
            Color value = result.rgb(pixel) + photon.power * scale;
            result.set_rgb(pixel, value);
            ++tile_pixels[tile];
          }
      }
    }
  });
  for (const SplatCounts& local : block_counts) {
    counts.splatted += local.splatted, counts.hidden += local.hidden;
    counts.clamped_small += local.clamped_small, counts.clamped_large += local.clamped_large;
    counts.splatted_flux += local.splatted_flux, counts.hidden_flux += local.hidden_flux;
  }
  for (uint64_t pixels : tile_pixels) counts.pixels += pixels;
  if (footprint_pixels) *footprint_pixels = std::move(unclamped);
  return result;
}

}  // namespace causticbench::rt_photons
