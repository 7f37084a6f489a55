// Splatting photons into the caustic map: one texel, a fixed Gaussian, or Wyman & Dachsbacher's
// variable-sized splats whose radius follows the photons' local density.
#include <algorithm>
#include <cmath>

#include "core/parallel.h"
#include "methods/caustic_mapping/pass_parts.h"

namespace causticbench::caustic_mapping {

namespace {

// The variable splats' density buffer: photons counted in cells of this many texels a side (Wyman &
// Dachsbacher count them in a coarse buffer rendered first). 4 keeps a focus a few texels wide from
// being averaged with its dark surroundings, while a cell still holds photons where they are sparse.
constexpr int kDensityCell = 4;

// Each photon's splat radius in texels (0: one texel, the point splat).
std::vector<float> splat_radii(const std::vector<LandedPhoton>& photons, const Settings& settings, int n) {
  std::vector<float> radii(photons.size(), 0.0f);
  if (settings.splat == SplatKind::gaussian) std::fill(radii.begin(), radii.end(), static_cast<float>(settings.splat_radius));
  if (settings.splat != SplatKind::variable) return radii;
  const int cells = (n + kDensityCell - 1) / kDensityCell;
  std::vector<uint32_t> counts(static_cast<size_t>(cells) * cells, 0);
  auto cell_of = [&](const LandedPhoton& photon) {
    const int x = std::clamp(static_cast<int>(photon.x) / kDensityCell, 0, cells - 1);
    const int y = std::clamp(static_cast<int>(photon.y) / kDensityCell, 0, cells - 1);
    return static_cast<size_t>(y) * cells + x;
  };
  for (const LandedPhoton& photon : photons) ++counts[cell_of(photon)];
  // The radius of a disc that holds splat_photons photons at the cell's density (photons per texel^2),
  // as a k-nearest-neighbour radius would: small at a focus, large where photons are sparse.
  for (size_t i = 0; i < photons.size(); ++i) {
    const double density = counts[cell_of(photons[i])] / double(kDensityCell * kDensityCell);
    const double radius = std::sqrt(settings.splat_photons / (kPiDouble * density));
    radii[i] = static_cast<float>(std::clamp(radius, 0.5, settings.max_splat_radius));
  }
  return radii;
}

// The Gaussian kernel of a splat of `radius` texels around (cx, cy), its standard deviation half the
// radius and cut at the radius: weight of texel (x, y), unnormalised.
double kernel(double radius, double cx, double cy, int x, int y) {
  const double dx = x + 0.5 - cx, dy = y + 0.5 - cy, d2 = dx * dx + dy * dy;
  if (d2 > radius * radius) return 0.0;
  const double sigma = 0.5 * radius;
  return std::exp(-d2 / (2.0 * sigma * sigma));
}

// The texels of one splat, clipped to the map: x0..x1, y0..y1 inclusive.
struct Footprint {
  int x0, x1, y0, y1;
};

Footprint footprint(const LandedPhoton& photon, float radius, int n) {
  if (radius <= 0.0f) {
    const int x = std::clamp(static_cast<int>(photon.x), 0, n - 1), y = std::clamp(static_cast<int>(photon.y), 0, n - 1);
    return {x, x, y, y};
  }
  return {std::max(0, static_cast<int>(std::floor(photon.x - radius))),
          std::min(n - 1, static_cast<int>(std::floor(photon.x + radius))),
          std::max(0, static_cast<int>(std::floor(photon.y - radius))),
          std::min(n - 1, static_cast<int>(std::floor(photon.y + radius)))};
}

}  // namespace

void splat_photons(const std::vector<LandedPhoton>& photons, const Settings& settings, int n, std::vector<double>& flux) {
  flux.assign(static_cast<size_t>(n) * n * 3, 0.0);
  if (photons.empty()) return;
  const std::vector<float> radii = splat_radii(photons, settings, n);
  // Photons by the first row they touch, in photon order within a row; each band of rows then adds the
  // photons that touch it in that order, so a texel's sum does not depend on the threads.
  std::vector<std::vector<uint32_t>> by_row(static_cast<size_t>(n));
  std::vector<Footprint> footprints(photons.size());
  for (size_t i = 0; i < photons.size(); ++i) {
    footprints[i] = footprint(photons[i], radii[i], n);
    by_row[static_cast<size_t>(footprints[i].y0)].push_back(static_cast<uint32_t>(i));
  }
  const int widest = static_cast<int>(std::ceil(*std::max_element(radii.begin(), radii.end()) * 2.0f)) + 1;
  constexpr int kBand = 16;
  parallel_blocks(static_cast<size_t>(n), kBand, [&](size_t begin, size_t end, size_t) {
    const int band_start = static_cast<int>(begin), band_end = static_cast<int>(end);  // rows [start, end)
    std::vector<double> weights;
    for (int row = std::max(0, band_start - widest); row < band_end; ++row) {
      for (uint32_t index : by_row[static_cast<size_t>(row)]) {
        const Footprint& box = footprints[index];
        if (box.y1 < band_start) continue;
        const LandedPhoton& photon = photons[index];
        const int width = box.x1 - box.x0 + 1;
        weights.assign(static_cast<size_t>(width) * (box.y1 - box.y0 + 1), 0.0);
        double total = 0.0;
        if (radii[index] <= 0.0f) {
          weights[0] = total = 1.0;
        } else {
          for (int y = box.y0; y <= box.y1; ++y)
            for (int x = box.x0; x <= box.x1; ++x) {
              const double w = kernel(radii[index], photon.x, photon.y, x, y);
              weights[static_cast<size_t>(y - box.y0) * width + (x - box.x0)] = w;
              total += w;
            }
          if (total <= 0.0) {  // a radius under half a texel that reached no texel centre: the nearest one
            const int x = std::clamp(static_cast<int>(photon.x), box.x0, box.x1);
            const int y = std::clamp(static_cast<int>(photon.y), box.y0, box.y1);
            weights[static_cast<size_t>(y - box.y0) * width + (x - box.x0)] = total = 1.0;
          }
        }
        for (int y = std::max(box.y0, band_start); y <= std::min(box.y1, band_end - 1); ++y)
          for (int x = box.x0; x <= box.x1; ++x) {
            const double w = weights[static_cast<size_t>(y - box.y0) * width + (x - box.x0)] / total;
            if (w == 0.0) continue;
            double* texel = &flux[(static_cast<size_t>(y) * n + x) * 3];
            for (int c = 0; c < 3; ++c) texel[c] += w * photon.flux[c];
          }
      }
    }
  });
}

}  // namespace causticbench::caustic_mapping
