#include <cmath>
#include <filesystem>
#include <stdexcept>

#include <fmt/format.h>

#include "apps/commands.h"
#include "core/errors.h"
#include "core/image.h"
#include "core/image_statistics.h"
#include "methods/frame_dump.h"

namespace causticbench {

namespace {

Image rgba_image(const std::vector<float>& rgba, uint32_t width, uint32_t height, const std::string& path) {
  if (rgba.size() != 4ull * width * height) throw InputError(path + ": expected " + std::to_string(width * height) + " RGBA pixels");
  Image image(static_cast<int>(width), static_cast<int>(height), 3);
  for (size_t pixel = 0; pixel < image.pixel_count(); ++pixel) {
    image.set_rgb(pixel, Color(rgba[4 * pixel], rgba[4 * pixel + 1], rgba[4 * pixel + 2]));
  }
  return image;
}

}  // namespace

// The dump's method (method.txt) decides how to read the frame's size and receivers and how closely the
// backends must agree (its FrameDumpFormat, registered by its folder).
int run_gpu_compare(const std::string& folder) {
  std::string cpu_path = folder + "/cpu_irradiance.bin", gpu_path = folder + "/vulkan_irradiance.bin";
  const FrameDumpFormat* format = nullptr;
  FrameDumpInfo info;
  std::vector<float> cpu_rgba, gpu_rgba;
  // A missing or malformed dump is the user's input, not an internal error (exit 2, not 1 = disagree).
  try {
    format = &frame_dump_format(read_dump_method(folder));
    info = format->read_info(folder);
    for (const std::string& path : {cpu_path, gpu_path}) {
      if (!std::filesystem::is_regular_file(path)) {
        throw InputError(path + ": not found; write the folder with `causticbench render ... --dump-frame " + folder +
                         "` (backend cpu) and run `causticbench-gpubench " + folder + "` first");
      }
    }
    cpu_rgba = read_floats(cpu_path);
    gpu_rgba = read_floats(gpu_path);
  } catch (const InputError&) {
    throw;
  } catch (const std::runtime_error& error) {
    throw InputError(error.what());
  }
  Image cpu = rgba_image(cpu_rgba, info.width, info.height, cpu_path);
  Image gpu = rgba_image(gpu_rgba, info.width, info.height, gpu_path);
  double relmse = relative_mse(gpu, cpu, info.receivers);
  double cpu_flux = masked_sum(cpu, info.receivers), gpu_flux = masked_sum(gpu, info.receivers);
  double ratio = cpu_flux > 0.0 ? gpu_flux / cpu_flux : (gpu_flux == 0.0 ? 1.0 : 0.0);
  bool agree = relmse <= format->relmse_tolerance && std::abs(ratio - 1.0) <= format->flux_tolerance;
  fmt::print("{}: {} vulkan against cpu: relMSE {:.3g} (tolerance {:g}), flux ratio {:.8f} (tolerance 1 +- {:g}): {}\n",
             folder, format->method, relmse, format->relmse_tolerance, ratio, format->flux_tolerance,
             agree ? "agree" : "DISAGREE");
  if (!agree) fmt::print("the tolerance: {}\n", format->tolerance_reason);
  return agree ? 0 : 1;
}

}  // namespace causticbench
