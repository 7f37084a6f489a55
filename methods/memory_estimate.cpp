#include "methods/memory_estimate.h"

#include <cstdlib>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "core/errors.h"
#include "methods/lifecycle.h"

namespace causticbench {

MemoryEstimate estimate_frame_memory(int width, int height, const MethodInfo& method) {
  const double pixels = static_cast<double>(width) * height;
  MemoryEstimate estimate;
  estimate.bytes = pixels * (kFrameBytesPerPixel + method.working_bytes_per_pixel) + kProcessBaseBytes;
  estimate.breakdown = fmt::format("{}x{} = {:.0f} pixels x ({:.0f} bytes of every frame + {:.0f} of {}) + {:.0f} MiB",
                                   width, height, pixels, kFrameBytesPerPixel, method.working_bytes_per_pixel,
                                   method.name, kProcessBaseBytes / 1048576.0);
  estimate.pixel_bytes = estimate.bytes - kProcessBaseBytes;
  estimate.method = method.name;
  return estimate;
}

MemoryEstimate estimate_run_memory(int width, int height, const CausticMethod& method, const PrepareContext& context,
                                   const ParamSet& knobs, int pixel_samples) {
  MemoryEstimate estimate = estimate_frame_memory(width, height, method.info());
  try {
    estimate.terms = method.knob_memory(context, knobs);
  } catch (const InputError&) {
    throw;
  } catch (...) {
    throw MethodError(fmt::format("knob_memory() of method {}: {}", method.info().name, current_exception_text()));
  }
  if (pixel_samples > 1) {
    const double bytes = pixel_samples_bytes(width, height, pixel_samples, context.frames.size());
    estimate.terms.push_back(MemoryTerm{{"pixel_samples"}, bytes,
                                        fmt::format("{} sub-pixel G-buffers of {:.0f} bytes a pixel, kept up to {:.0f} MiB, "
                                                    "and the mean's sums",
                                                    pixel_samples, kGBufferBytesPerPixel, kSubpixelCacheBytes / 1048576.0)});
  }
  for (const MemoryTerm& term : estimate.terms) {
    estimate.bytes += term.bytes;
    estimate.breakdown += fmt::format(" + {:.0f} MiB for {} ({})", term.bytes / 1048576.0, join(term.knobs, " and "),
                                      term.formula);
  }
  return estimate;
}

namespace {

// The first number in a file, or a negative value when it has none ("max" in memory.max).
double read_number(const std::string& path) {
  std::ifstream stream(path);
  double value = -1.0;
  if (!(stream >> value)) return -1.0;
  return value;
}

double meminfo_available_bytes() {
  std::ifstream stream("/proc/meminfo");
  for (std::string line; std::getline(stream, line);) {
    std::istringstream fields(line);
    std::string name;
    double kilobytes = 0.0;
    if (fields >> name >> kilobytes && name == "MemAvailable:") return kilobytes * 1024.0;
  }
  return -1.0;
}

}  // namespace

double available_memory_bytes() {
  if (const char* forced = std::getenv("CAUSTICBENCH_AVAILABLE_MEMORY")) {
    char* end = nullptr;
    double value = std::strtod(forced, &end);
    if (end != forced && *end == '\0' && value >= 0.0) return value;
    throw InputError(fmt::format("CAUSTICBENCH_AVAILABLE_MEMORY: expected a number of bytes, found '{}'", forced));
  }
  double available = meminfo_available_bytes();
  // A container's limit (cgroup v2) bounds what this process may take whatever the host has free.
  double limit = read_number("/sys/fs/cgroup/memory.max"), used = read_number("/sys/fs/cgroup/memory.current");
  if (limit > 0.0 && used >= 0.0 && (available < 0.0 || limit - used < available)) available = limit - used;
  return available;
}

void check_memory_fits(const MemoryEstimate& estimate, const std::string& what) {
  const double available = available_memory_bytes();
  if (available < 0.0 || estimate.bytes <= available) return;  // unknown: nothing to refuse on
  constexpr double kGiB = 1024.0 * 1024.0 * 1024.0;
  // The largest part says what to lower: a knob of the method, or the resolution.
  const MemoryTerm* largest = nullptr;
  for (const MemoryTerm& term : estimate.terms)
    if (!largest || term.bytes > largest->bytes) largest = &term;
  if (largest && largest->bytes >= estimate.pixel_bytes) {
    std::string quoted;
    for (size_t k = 0; k < largest->knobs.size(); ++k)
      quoted += (k == 0 ? "" : k + 1 == largest->knobs.size() ? " and " : ", ") + ("'" + largest->knobs[k] + "'");
    throw InputError(fmt::format("{}: knob{} {} of {}: expected a setting whose run fits in the available memory ({:.1f} "
                                 "GiB), found an estimate of {:.1f} GiB, {:.1f} GiB of it for {}; lower {}",
                                 what, largest->knobs.size() == 1 ? "" : "s", quoted, estimate.method, available / kGiB, estimate.bytes / kGiB,
                                 largest->bytes / kGiB, largest->formula, join(largest->knobs, " or ")));
  }
  throw InputError(fmt::format("{}: expected a frame that fits in the available memory ({:.1f} GiB), found an estimate "
                               "of {:.1f} GiB ({}); lower the resolution",
                               what, available / kGiB, estimate.bytes / kGiB, estimate.breakdown));
}

}  // namespace causticbench
