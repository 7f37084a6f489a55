#include "methods/lpi/volume_radius.h"

#include <cmath>

namespace causticbench::lpi {

namespace {

// Cells (or shells) the storage puts across the ball's diameter.
double cells_across(const VolumeSettings& settings) {
  switch (settings.storage) {
    case StorageKind::grid:
    case StorageKind::sh: return settings.grid_resolution;
    case StorageKind::multires: return std::ldexp(1.0, settings.multires_depth);
    case StorageKind::shells: return 2.0 * settings.shell_count;
  }
  return 0.0;
}

}  // namespace

double volume_radius_cap(const VolumeSettings& settings) { return ball_radius_cap(cells_across(settings)); }

VolumeRadius choose_volume_radius(const PrepareContext& context, int object, const BoundingSphere& build_bounds,
                                  const VolumeSettings& settings) {
  return choose_ball_radius(context, object, build_bounds, settings.volume_radius, cells_across(settings));
}

}  // namespace causticbench::lpi
