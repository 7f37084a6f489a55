// How much memory a frame of a method takes at a resolution, and whether this machine has it: checked
// before any work starts, so that `render -r 16384x16384` or an experiment variant at that size stops
// with the estimate and exit code 2 instead of running for minutes and ending in std::bad_alloc.
//
// The estimate has two parts. Per pixel: what every frame holds (the G-buffer, the E_c and direct
// images, the composite and the encoded output files, kFrameBytesPerPixel) plus the method's own
// per-pixel working memory (MethodInfo::working_bytes_per_pixel), both measured as the growth of the
// peak resident size between two resolutions (docs/results-format.md, "Memory"). Per knob: what the
// method's knobs cost on this scene (CausticMethod::knob_memory: a photon count, a precomputed
// volume), so that `multires_depth: 9` is refused naming multires_depth rather than run to 17 GB.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/scene.h"
#include "methods/method.h"

namespace causticbench {

// Bytes per pixel that every frame holds whatever the method.
constexpr double kFrameBytesPerPixel = 240.0;
// Fixed cost of the process beside the pixels (libraries, the scene's ray tracer for small scenes).
constexpr double kProcessBaseBytes = 160.0 * 1024 * 1024;

struct MemoryEstimate {
  double bytes = 0.0;
  std::string breakdown;  // "512x512 = 262144 pixels x (240 bytes of every frame + 153 of reference) + 160 MiB"
  double pixel_bytes = 0.0;        // the part that grows with the pixels
  std::vector<MemoryTerm> terms;   // the parts that grow with knobs
  std::string method;
};

MemoryEstimate estimate_frame_memory(int width, int height, const MethodInfo& method);
// The frame's memory and the method's knob terms on this scene (`knobs`: every phase, resolved), and with
// `pixel_samples` > 1 the harness's term for it (methods/lifecycle.h, pixel_samples_bytes) named
// pixel_samples.
MemoryEstimate estimate_run_memory(int width, int height, const CausticMethod& method, const PrepareContext& context,
                                   const ParamSet& knobs, int pixel_samples = 1);

// Bytes this process may still take: the system's MemAvailable, bounded by the cgroup's memory.max
// where one is set. CAUSTICBENCH_AVAILABLE_MEMORY (bytes) replaces the measurement, for tests and for
// sharing a machine with other work.
double available_memory_bytes();

// InputError "`what`: expected a frame that fits in the available memory (X GiB), found about Y GiB
// (breakdown)" when the estimate exceeds what is available; where a knob term is the larger part, the
// message names its knobs and their values ("lower multires_depth") instead of the resolution.
void check_memory_fits(const MemoryEstimate& estimate, const std::string& what);

}  // namespace causticbench
