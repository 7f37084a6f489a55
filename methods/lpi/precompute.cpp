#include "methods/lpi/precompute.h"

#include <chrono>
#include <stdexcept>

#include "core/parallel.h"
#include "core/tracer.h"
#include "methods/lpi/grid_layout.h"
#include "methods/lpi/shell_layout.h"

namespace causticbench::lpi {

std::unique_ptr<VolumeLayout> make_layout(const VolumeSettings& settings, const BoundingSphere& bounds) {
  const float radius = static_cast<float>(settings.volume_radius) * bounds.radius;
  if (settings.storage == StorageKind::grid) {
    return std::make_unique<GridLayout>(bounds.center, radius, settings.grid_resolution);
  }
  return std::make_unique<ShellLayout>(bounds.center, radius, settings.shell_count, settings.shell_subdivision,
                                       static_cast<ShellSpacing>(settings.shell_spacing));
}

void shoot_light_samples(const Scene& build_scene, const VolumeSettings& settings, ObjectVolumes& volumes,
                         const std::function<void(size_t, size_t)>& report) {
  const auto start = std::chrono::steady_clock::now();
  SceneFrame frame(build_scene, 0.0);
  Tracer tracer(frame);
  const VolumeLayout& layout = *volumes.layout;
  const int channels = channel_count(settings.orientation);
  const size_t values_per_sample = layout.points() * static_cast<size_t>(channels);
  const size_t sample_count = volumes.samples.directions.size();
  std::vector<float> all_values(values_per_sample * sample_count, 0.0f);
  // Fixed chunks, summed in chunk order a wave at a time: the same sums for any thread count, and
  // memory for eight chunk accumulators rather than one per photon block.
  const uint64_t chunk_size = 32768;
  const size_t wave = 8;
  std::vector<std::vector<float>> chunk_sums(wave, std::vector<float>(values_per_sample));
  std::vector<PhotonStats> chunk_stats(wave);
  std::vector<double> total(values_per_sample);
  for (size_t sample = 0; sample < sample_count; ++sample) {
    PhotonLights lights;
    lights.add_directional(volumes.samples.directions[sample], Color(1.0f), 0.0);
    CausticPhotonTracer photon_tracer(tracer, PhotonTracerSettings{settings.seed}, lights.frames(), {0});
    std::fill(total.begin(), total.end(), 0.0);
    const uint64_t photons = settings.photons_per_sample;
    const uint64_t chunks = (photons + chunk_size - 1) / chunk_size;
    const uint64_t first_index = static_cast<uint64_t>(sample) << 32;
    for (uint64_t wave_start = 0; wave_start < chunks; wave_start += wave) {
      const size_t in_wave = static_cast<size_t>(std::min<uint64_t>(wave, chunks - wave_start));
      parallel_blocks(in_wave, 1, [&](size_t slot, size_t, size_t) {
        std::vector<float>& sums = chunk_sums[slot];
        std::fill(sums.begin(), sums.end(), 0.0f);
        chunk_stats[slot] = PhotonStats{};
        const uint64_t begin = (wave_start + slot) * chunk_size, end = std::min(photons, begin + chunk_size);
        auto deposit = [&](const PathSegment& segment) { layout.deposit(segment, settings.orientation, sums.data()); };
        for (uint64_t i = begin; i < end; ++i) photon_tracer.trace_segments(first_index + i, chunk_stats[slot], deposit);
      });
      for (size_t slot = 0; slot < in_wave; ++slot) {
        const std::vector<float>& sums = chunk_sums[slot];
        for (size_t i = 0; i < values_per_sample; ++i) total[i] += sums[i];
        volumes.stats.add(chunk_stats[slot]);
      }
    }
    layout.normalise(static_cast<double>(photons), settings.orientation, total.data());
    float* output = all_values.data() + sample * values_per_sample;
    for (size_t i = 0; i < values_per_sample; ++i) output[i] = static_cast<float>(total[i]);
    if (report) report(sample + 1, sample_count);
  }
  volumes.values = StoredValues::encode(settings.precision, channels, settings.orientation == Orientation::vector,
                                        layout.points(), all_values);
  volumes.shoot_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace causticbench::lpi
