#include <filesystem>

#include <fmt/format.h>

#include "apps/commands.h"
#include "core/errors.h"
#include "core/image.h"
#include "core/image_statistics.h"
#include "methods/pinhole/frame_data.h"

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

// The tolerance: both backends do the same float arithmetic in a different order and with different
// square roots and divisions, so they differ by rounding only: relMSE below 1e-6 and total flux within
// 1e-4. A real disagreement (a wrong texel, a missed sample) is orders of magnitude larger.
int run_gpu_compare(const std::string& folder) {
  std::string cpu_path = folder + "/cpu_irradiance.bin", gpu_path = folder + "/vulkan_irradiance.bin";
  for (const std::string& path : {folder + "/frame.txt", cpu_path, gpu_path}) {
    if (!std::filesystem::is_regular_file(path)) {
      throw InputError(path + ": not found; write the folder with `causticbench render ... --dump-frame " + folder +
                       "` (backend cpu) and run `causticbench-gpubench " + folder + "` first");
    }
  }
  PinholeFrameData frame = read_frame_data(folder);
  Image cpu = rgba_image(read_floats(cpu_path), frame.width, frame.height, cpu_path);
  Image gpu = rgba_image(read_floats(gpu_path), frame.width, frame.height, gpu_path);
  std::vector<uint8_t> mask(frame.pixel_count());
  for (uint32_t pixel = 0; pixel < frame.pixel_count(); ++pixel) mask[pixel] = frame.is_receiver(pixel);
  double relmse = relative_mse(gpu, cpu, mask);
  double cpu_flux = masked_sum(cpu, mask), gpu_flux = masked_sum(gpu, mask);
  double ratio = cpu_flux > 0.0 ? gpu_flux / cpu_flux : (gpu_flux == 0.0 ? 1.0 : 0.0);
  bool agree = relmse <= 1e-6 && std::abs(ratio - 1.0) <= 1e-4;
  fmt::print("{}: vulkan against cpu: relMSE {:.3g} (tolerance 1e-6), flux ratio {:.8f} (tolerance 1 +- 1e-4): {}\n", folder,
             relmse, ratio, agree ? "agree" : "DISAGREE");
  return agree ? 0 : 1;
}

}  // namespace causticbench
