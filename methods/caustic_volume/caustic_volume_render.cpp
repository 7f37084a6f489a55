// caustic_volume's render: each volume tested against the receiver points its screen footprint covers,
// the CPU's version of rasterising the volume's boundary over the G-buffer (Ernst et al.'s fill cost).
#include <algorithm>
#include <atomic>
#include <cmath>

#include "core/parallel.h"
#include "methods/caustic_volume/caustic_volume.h"

namespace causticbench {

namespace {

// The pixels of row `row` whose centres lie within a pixel of the convex `hull`: [begin, end), empty
// when none.
std::pair<int, int> row_span(const std::vector<glm::dvec2>& hull, int row, int width) {
  const double y = row + 0.5;
  double low = std::numeric_limits<double>::infinity(), high = -low;
  const size_t n = hull.size();
  for (size_t i = 0; i < n; ++i) {
    const glm::dvec2& a = hull[i];
    const glm::dvec2& b = hull[(i + 1) % n];
    // The edge's x over the band [y - 1, y + 1] (a pixel of margin), at its ends within the band.
    const double y0 = std::max(std::min(a.y, b.y), y - 1.0), y1 = std::min(std::max(a.y, b.y), y + 1.0);
    if (y0 > y1) continue;
    for (double at : {y0, y1}) {
      const double x = a.y == b.y ? a.x : a.x + (b.x - a.x) * (at - a.y) / (b.y - a.y);
      low = std::min({low, x, a.y == b.y ? b.x : x});
      high = std::max({high, x, a.y == b.y ? b.x : x});
    }
  }
  if (n == 1) low = high = hull[0].x;
  if (!(low <= high)) return {0, 0};
  return {std::clamp(static_cast<int>(std::floor(low - 1.0)), 0, width),
          std::clamp(static_cast<int>(std::ceil(high + 1.0)), 0, width)};
}

}  // namespace

Image CausticVolumeMethod::render(const GBuffer& gbuffer, const ParamSet& render) {
  const caustic_volume::Intensity intensity = render.text("intensity") == "constant"
                                                  ? caustic_volume::Intensity::constant
                                                  : caustic_volume::Intensity::interpolated;
  if (render.has("backend") && render.text("backend") == "vulkan") return render_on_device(gbuffer, intensity);
  const bool shadow_rays = render.text("occlusion") == "shadow_rays" && tracer_ != nullptr;
  Image result(gbuffer.width, gbuffer.height, 3);
  constexpr int kBand = 8;  // rows a task; each pixel adds its volumes in their order: deterministic
  const int width = gbuffer.width, height = gbuffer.height;
  std::atomic<uint64_t> tests{0}, sheets{0}, rays{0};
  parallel_blocks(static_cast<size_t>(height), kBand, [&](size_t begin, size_t end, size_t) {
    const int row_begin = static_cast<int>(begin), row_end = static_cast<int>(end);
    std::vector<Color> sums(static_cast<size_t>(width) * (row_end - row_begin), Color(0.0f));
    uint64_t band_tests = 0, band_sheets = 0, band_rays = 0;
    for (size_t v = 0; v < volumes_.size(); ++v) {
      const Footprint& footprint = footprints_[v];
      const int first = std::max(row_begin, footprint.row_begin), last = std::min(row_end, footprint.row_end);
      for (int row = first; row < last; ++row) {
        const auto [x0, x1] = footprint.whole_image ? std::pair<int, int>{0, width} : row_span(footprint.hull, row, width);
        for (int x = x0; x < x1; ++x) {
          const size_t pixel = static_cast<size_t>(row) * width + x;
          if (!gbuffer.receiver[pixel]) continue;
          ++band_tests;
          const caustic_volume::Volume& volume = volumes_[v];
          const double t_min = gbuffer.object[pixel] == volume.object ? volume.self_gap : 0.0;
          const glm::dvec3 point(gbuffer.position[pixel]), normal(gbuffer.normal[pixel]);
          Color added(0.0f);
          if (!shadow_rays) {
            added = caustic_volume::volume_irradiance(volume, point, normal, intensity, t_min);
          } else {
            // Each sheet's light, if the way back to where it left the surface is clear (short of the
            // surface by its self gap, more than the sagitta by which the exact shape departs from the
            // triangle, so that the shape does not shadow its own light).
            caustic_volume::Sheet sheets[3];
            const int count = caustic_volume::sheets_through(volume, point, sheets, t_min);
            for (int s = 0; s < count; ++s) {
              const auto& w = sheets[s].weights;
              const glm::dvec3 start = w[0] * volume.origin[0] + w[1] * volume.origin[1] + w[2] * volume.origin[2];
              const glm::dvec3 back = start - point;
              const double distance = glm::length(back);
              ++band_rays;
              const glm::dvec3 origin = point + normal * double(tracer_->epsilon()) * (glm::dot(normal, back) >= 0.0 ? 1.0 : -1.0);
              if (distance > volume.self_gap &&
                  tracer_->occluded(Vec3(origin), Vec3(back / distance), static_cast<float>(distance - volume.self_gap)))
                continue;
              added += caustic_volume::sheet_irradiance(volume, sheets[s], point, normal, intensity);
            }
          }
          if (added.r > 0.0f || added.g > 0.0f || added.b > 0.0f) ++band_sheets;
          sums[static_cast<size_t>(row - row_begin) * width + x] += added;
        }
      }
    }
    for (int row = row_begin; row < row_end; ++row)
      for (int x = 0; x < width; ++x)
        result.set_rgb(static_cast<size_t>(row) * width + x, sums[static_cast<size_t>(row - row_begin) * width + x]);
    tests += band_tests;
    sheets += band_sheets;
    rays += band_rays;
  });
  point_tests_ = tests.load();
  sheets_ = sheets.load();
  shadow_rays_ = rays.load();
  return result;
}

}  // namespace causticbench
