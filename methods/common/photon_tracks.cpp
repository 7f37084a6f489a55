#include "methods/common/photon_tracks.h"

#include <algorithm>

#include "core/parallel.h"

namespace causticbench {

namespace {

constexpr uint64_t kChunkSize = 32768;  // photons a chunk
constexpr size_t kWave = 8;             // chunks traced at once

}  // namespace

PhotonTrackSums::PhotonTrackSums(size_t values)
    : values_(values), chunk_sums_(kWave, std::vector<float>(values)), chunk_stats_(kWave), total_(values) {}

std::vector<double>& PhotonTrackSums::accumulate(const CausticPhotonTracer& tracer, uint64_t first_index,
                                                 uint64_t photons,
                                                 const std::function<void(const PathSegment&, float*)>& deposit,
                                                 PhotonStats& stats) {
  std::fill(total_.begin(), total_.end(), 0.0);
  const uint64_t chunks = (photons + kChunkSize - 1) / kChunkSize;
  for (uint64_t wave_start = 0; wave_start < chunks; wave_start += kWave) {
    const size_t in_wave = static_cast<size_t>(std::min<uint64_t>(kWave, chunks - wave_start));
    parallel_blocks(in_wave, 1, [&](size_t slot, size_t, size_t) {
      std::vector<float>& sums = chunk_sums_[slot];  // zero: from the start, or the reduction below
      chunk_stats_[slot] = PhotonStats{};
      const uint64_t begin = (wave_start + slot) * kChunkSize, end = std::min(photons, begin + kChunkSize);
      auto visit = [&](const PathSegment& segment) { deposit(segment, sums.data()); };
      for (uint64_t i = begin; i < end; ++i) tracer.trace_segments(first_index + i, chunk_stats_[slot], visit);
    });
    // Each value sums the chunks in chunk order whatever the thread count; split over values, the
    // reduction runs on every core, and it zeroes the chunk sums for the next wave while they are in cache.
    parallel_blocks(values_, 1 << 16, [&](size_t first, size_t last, size_t) {
      for (size_t slot = 0; slot < in_wave; ++slot) {
        float* sums = chunk_sums_[slot].data();
        for (size_t i = first; i < last; ++i) {
          total_[i] += sums[i];
          sums[i] = 0.0f;
        }
      }
    });
    for (size_t slot = 0; slot < in_wave; ++slot) stats.add(chunk_stats_[slot]);
  }
  return total_;
}

}  // namespace causticbench
