// causticbench-gpubench: replays a frame that `causticbench render ... --dump-frame DIR` wrote on the
// first Vulkan device (a real GPU before lavapipe), and writes its caustic irradiance and timings.
// DIR/method.txt names the method; its FrameDumpFormat (registered by its folder, cmake/methods.cmake) reads and replays the
// rest, so this file knows no method. Links only the Vulkan loader (and libstdc++ statically), so that
// it runs on GPU machines that have none of causticbench's other dependencies. Compare with
// `causticbench gpu-compare DIR`.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "gpu/vulkan_context.h"
#include "methods/frame_dump.h"

namespace {

using namespace causticbench;

int usage(const char* program) {
  std::string methods;
  for (const FrameDumpFormat& format : frame_dump_formats()) methods += (methods.empty() ? "" : ", ") + format.method;
  std::fprintf(stderr,
               "usage: %s DUMP_DIR [--repetitions N]\n"
               "  Replays the frame in DUMP_DIR (from causticbench render --method METHOD --dump-frame DUMP_DIR)\n"
               "  on the first Vulkan device, after one warm-up, N times (default 10). DUMP_DIR/method.txt names\n"
               "  the method; any method whose folder registers a dump format can be replayed:\n"
               "  %s. Writes DUMP_DIR/vulkan_irradiance.bin (RGBA float32 per pixel) and DUMP_DIR/gpu_timings.json,\n"
               "  and prints the device, the median and minimum kernel time from timestamp queries, the method's\n"
               "  evaluations per second, and the facts its replay reports (docs/gpu.md).\n",
               program, methods.c_str());
  return 2;
}

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

// The replay's facts (one JSON member a line) indented for gpu_timings.json, and on one line for stdout.
std::string indented_facts(const std::string& facts, const std::string& separator) {
  std::istringstream lines(facts);
  std::string line, text;
  while (std::getline(lines, line)) text += separator + line;
  return text;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) return usage(argv[0]);
  std::string folder = argv[1];
  int repetitions = 10;
  for (int i = 2; i < argc; ++i) {
    std::string argument = argv[i];
    if (argument == "--repetitions" && i + 1 < argc) {
      repetitions = std::atoi(argv[++i]);
      if (repetitions < 1) return usage(argv[0]);
    } else {
      return usage(argv[0]);
    }
  }
  try {
    const FrameDumpFormat& format = frame_dump_format(read_dump_method(folder));
    FrameDumpInfo info = format.read_info(folder);
    gpu::Context context;
    std::unique_ptr<FrameReplay> replay = format.replay(context, folder);
    double kernel_milliseconds = 0.0;
    std::vector<float> irradiance = replay->render(kernel_milliseconds);  // warm-up
    if (irradiance.size() != 4ull * info.width * info.height) {
      throw std::runtime_error(format.method + " replay: returned " + std::to_string(irradiance.size()) +
                               " floats, expected RGBA for " + std::to_string(info.width) + " x " +
                               std::to_string(info.height) + " pixels");
    }
    std::vector<double> kernel_ms, wall_ms;
    for (int r = 0; r < repetitions; ++r) {
      auto start = std::chrono::steady_clock::now();
      irradiance = replay->render(kernel_milliseconds);
      wall_ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
      kernel_ms.push_back(kernel_milliseconds);
    }
    size_t receivers = static_cast<size_t>(
        std::count_if(info.receivers.begin(), info.receivers.end(), [](uint8_t receiver) { return receiver != 0; }));
    double kernel = median(kernel_ms), minimum = *std::min_element(kernel_ms.begin(), kernel_ms.end());
    double rate = kernel > 0.0 ? info.evaluations / (kernel * 1e-3) : 0.0;
    std::string facts = replay->facts_json();
    write_floats(folder + "/vulkan_irradiance.bin", irradiance);
    std::ostringstream json;
    json.precision(9);
    json << "{\n  \"device\": " << json_quoted(context.device_name())
         << ",\n  \"cpu_device\": " << (context.is_cpu_device() ? "true" : "false")
         << ",\n  \"method\": " << json_quoted(format.method) << ",\n  \"repetitions\": " << repetitions
         << ",\n  \"kernel_ms_median\": " << kernel << ",\n  \"kernel_ms_min\": " << minimum
         << ",\n  \"wall_ms_median\": " << median(wall_ms) << ",\n  \"evaluations\": " << info.evaluations
         << ",\n  \"evaluation_unit\": " << json_quoted(format.evaluation_unit)
         << ",\n  \"evaluations_per_second\": " << rate << (facts.empty() ? "" : ",") << indented_facts(facts, "\n  ")
         << "\n}\n";
    write_dump_bytes(folder + "/gpu_timings.json", json.str().data(), json.str().size());
    std::printf("device %s: %s, %u x %u pixels (%zu receivers), %.3g %s, kernel median %.3f ms (min %.3f), "
                "wall median %.3f ms, %.3g evaluations/s\n",
                context.device_name().c_str(), format.method.c_str(), info.width, info.height, receivers,
                info.evaluations, format.evaluation_unit.c_str(), kernel, minimum, median(wall_ms), rate);
    if (!facts.empty()) std::printf("%s facts: {%s }\n", format.method.c_str(), indented_facts(facts, " ").c_str());
  } catch (const std::exception& error) {
    std::fprintf(stderr, "error: %s\n", error.what());
    return 1;
  }
  return 0;
}
