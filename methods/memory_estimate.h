// How much memory a frame of a method takes at a resolution, and whether this machine has it: checked
// before any work starts, so that `render -r 16384x16384` or an experiment variant at that size stops
// with the estimate and exit code 2 instead of running for minutes and ending in std::bad_alloc.
//
// The estimate is per pixel: what every frame holds (the G-buffer, the E_c and direct images, the
// composite and the encoded output files, kFrameBytesPerPixel) plus the method's own per-pixel working
// memory (MethodInfo::working_bytes_per_pixel). Both were measured as the growth of the peak resident
// size between two resolutions (docs/results-format.md, "Memory"). Memory that depends on knobs rather
// than on pixels (a photon count, a precomputed volume) is not in it: the method reports it afterwards
// as memory_bytes.
#pragma once

#include <cstdint>
#include <string>

#include "core/scene.h"
#include "methods/method.h"

namespace causticbench {

// Bytes per pixel that every frame holds whatever the method.
constexpr double kFrameBytesPerPixel = 240.0;
// Fixed cost of the process beside the pixels (libraries, the scene's ray tracer for small scenes).
constexpr double kProcessBaseBytes = 160.0 * 1024 * 1024;

struct MemoryEstimate {
  double bytes = 0.0;
  std::string breakdown;  // "512x512 = 262144 pixels x (240 bytes of every frame + 24 of reference) + 160 MiB"
};

MemoryEstimate estimate_frame_memory(int width, int height, const MethodInfo& method);

// Bytes this process may still take: the system's MemAvailable, bounded by the cgroup's memory.max
// where one is set. CAUSTICBENCH_AVAILABLE_MEMORY (bytes) replaces the measurement, for tests and for
// sharing a machine with other work.
double available_memory_bytes();

// InputError "`what`: expected a frame that fits in the available memory (X GiB), found about Y GiB
// (breakdown)" when the estimate exceeds what is available.
void check_memory_fits(const MemoryEstimate& estimate, const std::string& what);

}  // namespace causticbench
