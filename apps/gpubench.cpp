// causticbench-gpubench: replays a frame that `causticbench render ... --dump-frame DIR` wrote on the
// first Vulkan device (a real GPU before lavapipe), and writes its caustic irradiance and timings.
// Links only the Vulkan loader (and libstdc++ statically), so that it runs on GPU machines that have
// none of causticbench's other dependencies. Compare with `causticbench gpu-compare DIR`.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "gpu/cube_filter_check.h"
#include "gpu/vulkan_context.h"
#include "methods/pinhole/frame_data.h"
#include "methods/pinhole/vulkan_pinhole.h"

namespace {

int usage(const char* program) {
  std::fprintf(stderr,
               "usage: %s DUMP_DIR [--repetitions N]\n"
               "  Replays the pinhole frame in DUMP_DIR (from causticbench render --method pinhole --dump-frame DUMP_DIR)\n"
               "  on the first Vulkan device, after one warm-up, N times (default 10). Writes DUMP_DIR/vulkan_irradiance.bin\n"
               "  (RGBA float32 per pixel) and DUMP_DIR/gpu_timings.json, and prints the device, the median and minimum\n"
               "  kernel time from timestamp queries, and sample evaluations per second. First it checks that the device's\n"
               "  isotropic and anisotropic cube-map filtering follow textureGrad's gradients (gpu/cube_filter_check.h).\n",
               program);
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace causticbench;
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
    PinholeFrameData frame = read_frame_data(folder);
    gpu::Context context;
    // Whether this device's filtered lookups mean what textureGrad says (see gpu/cube_filter_check.h).
    gpu::CubeFilterCheck isotropic = gpu::check_cube_filtering(context, false);
    gpu::CubeFilterCheck anisotropic = gpu::check_cube_filtering(context, true);
    std::printf("sampler check: %s; %s\n", isotropic.summary().c_str(), anisotropic.summary().c_str());
    VulkanPinhole pinhole(context);
    pinhole.upload_frame(frame);
    double gpu_ms = 0.0;
    std::vector<float> irradiance = pinhole.render(frame, gpu_ms);  // warm-up
    std::vector<double> kernel_ms, wall_ms;
    for (int r = 0; r < repetitions; ++r) {
      auto start = std::chrono::steady_clock::now();
      irradiance = pinhole.render(frame, gpu_ms);
      wall_ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
      kernel_ms.push_back(gpu_ms);
    }
    auto median = [](std::vector<double> values) {
      std::sort(values.begin(), values.end());
      return values[values.size() / 2];
    };
    size_t receivers = 0;
    for (uint32_t pixel = 0; pixel < frame.pixel_count(); ++pixel) receivers += frame.is_receiver(pixel);
    double evaluations = static_cast<double>(receivers) * frame.sample_count();
    double kernel = median(kernel_ms), minimum = *std::min_element(kernel_ms.begin(), kernel_ms.end());
    write_floats(folder + "/vulkan_irradiance.bin", irradiance);
    std::ofstream json(folder + "/gpu_timings.json");
    json << "{\n  \"device\": \"" << context.device_name() << "\",\n  \"cpu_device\": " << (context.is_cpu_device() ? "true" : "false")
         << ",\n  \"repetitions\": " << repetitions << ",\n  \"kernel_ms_median\": " << kernel << ",\n  \"kernel_ms_min\": " << minimum
         << ",\n  \"wall_ms_median\": " << median(wall_ms) << ",\n  \"sample_evaluations\": " << evaluations
         << ",\n  \"evaluations_per_second\": " << (kernel > 0.0 ? evaluations / (kernel * 1e-3) : 0.0)
         << ",\n  \"filtering\": " << frame.filtering
         << ",\n  \"isotropic_filtering_honours_gradients\": " << (isotropic.honours_gradients ? "true" : "false")
         << ",\n  \"anisotropic_filtering_honours_gradients\": " << (anisotropic.honours_gradients ? "true" : "false")
         << "\n}\n";
    std::printf("device %s: %u x %u pixels (%zu receivers) x %u samples, kernel median %.3f ms (min %.3f), wall median %.3f ms, "
                "%.3g evaluations/s\n",
                context.device_name().c_str(), frame.width, frame.height, receivers, frame.sample_count(), kernel, minimum,
                median(wall_ms), kernel > 0.0 ? evaluations / (kernel * 1e-3) : 0.0);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "error: %s\n", error.what());
    return 1;
  }
  return 0;
}
