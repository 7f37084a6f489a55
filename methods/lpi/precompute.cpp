#include "methods/lpi/precompute.h"

#include <chrono>
#include <optional>
#include <stdexcept>

#include "core/tracer.h"
#include "methods/common/grid_layout.h"
#include "methods/common/photon_tracks.h"
#include "methods/lpi/harmonic_storage.h"
#include "methods/lpi/multires_layout.h"
#include "methods/common/spherical_harmonics.h"
#include "methods/lpi/shell_layout.h"

namespace causticbench::lpi {

std::unique_ptr<VolumeLayout> make_layout(const VolumeSettings& settings, const BoundingSphere& bounds,
                                          double radius_in_bounding_radii) {
  const float radius = static_cast<float>(radius_in_bounding_radii) * bounds.radius;
  if (settings.storage == StorageKind::grid || settings.storage == StorageKind::sh) {
    return std::make_unique<GridLayout>(bounds.center, radius, settings.grid_resolution);
  }
  if (settings.storage == StorageKind::multires) {
    return std::make_unique<MultiresLayout>(bounds.center, radius, settings.multires_depth, settings.error_threshold,
                                            settings.multires_tree);
  }
  return std::make_unique<ShellLayout>(bounds.center, radius, settings.shell_count, settings.shell_subdivision,
                                       static_cast<ShellSpacing>(settings.shell_spacing));
}

size_t stored_blocks(const VolumeSettings& settings, const ObjectVolumes& volumes) {
  return settings.storage == StorageKind::sh ? static_cast<size_t>(coefficient_count(settings.sh_order + 1))
                                             : volumes.samples.directions.size();
}

double bytes_per_light_sample(const ObjectVolumes& volumes) {
  const double samples = static_cast<double>(std::max<size_t>(1, volumes.samples.directions.size()));
  // The harmonic coefficients, and the blocks of a tree per light sample (each its own size): the
  // mean over the light samples.
  if (volumes.harmonic || !volumes.values.uniform_blocks()) {
    return (static_cast<double>(volumes.values.bytes().size()) + static_cast<double>(volumes.layout->index_bytes())) /
           samples;
  }
  return static_cast<double>(volumes.values.bytes_per_light_sample()) +
         static_cast<double>(volumes.layout->index_bytes()) / samples;
}

void shoot_light_samples(const Scene& build_scene, const VolumeSettings& settings, ObjectVolumes& volumes,
                         const std::function<void(size_t, size_t)>& report) {
  const auto start = std::chrono::steady_clock::now();
  SceneFrame frame(build_scene, 0.0);
  Tracer tracer(frame);
  VolumeLayout& layout = *volumes.layout;
  const int channels = channel_count(settings.orientation);
  const size_t values_per_sample = layout.deposit_points() * static_cast<size_t>(channels);
  // Refused before any photon is shot.
  std::optional<HarmonicFit> harmonic_fit;
  if (settings.storage == StorageKind::sh) {
    harmonic_fit.emplace(settings.sh_order, volumes.samples.directions, light_sample_areas(volumes.samples));
  }
  const size_t sample_count = volumes.samples.directions.size();
  std::vector<float> all_values(values_per_sample * sample_count, 0.0f);
  PhotonTrackSums sums(values_per_sample);
  auto deposit = [&](const PathSegment& segment, float* values) { layout.deposit(segment, settings.orientation, values); };
  for (size_t sample = 0; sample < sample_count; ++sample) {
    PhotonLights lights;
    lights.add_directional(volumes.samples.directions[sample], Color(1.0f), 0.0);
    CausticPhotonTracer photon_tracer(tracer, PhotonTracerSettings{settings.seed}, lights.frames(), {0});
    const uint64_t photons = settings.photons_per_sample;
    const uint64_t first_index = volumes.samples.seed_index(sample) << 32;
    std::vector<double>& total = sums.accumulate(photon_tracer, first_index, photons, deposit, volumes.stats);
    layout.normalise(static_cast<double>(photons), settings.orientation, total.data());
    float* output = all_values.data() + sample * values_per_sample;
    for (size_t i = 0; i < values_per_sample; ++i) output[i] = static_cast<float>(total[i]);
    if (report) report(sample + 1, sample_count);
  }
  bool signed_channels = settings.orientation == Orientation::vector;
  if (layout.adaptive()) all_values = layout.adapt(all_values, channels);
  if (harmonic_fit) {
    all_values = harmonic_fit->fit(all_values, values_per_sample);
    signed_channels = true;  // coefficients of any sign
  }
  volumes.harmonic = harmonic_fit.has_value();
  volumes.values = per_sample_trees(settings)
                      ? StoredValues::encode(settings.precision, channels, signed_channels,
                                             layout.block_points(sample_count), all_values)
                      : StoredValues::encode(settings.precision, channels, signed_channels, layout.points(), all_values);
  volumes.shoot_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace causticbench::lpi
