#include "methods/external/program_output.h"

#include <cmath>
#include <filesystem>

#include <fmt/format.h>

#include "core/files.h"

namespace causticbench {

Image read_program_image(const std::string& path, int width, int height) {
  if (!std::filesystem::is_regular_file(path)) throw std::runtime_error(fmt::format("it wrote no image at {}", path));
  Image image;
  try {
    image = read_exr(path);
  } catch (const std::exception& error) {
    throw std::runtime_error(fmt::format("its image is not a readable EXR ({})", error.what()));
  }
  if (image.width() != width || image.height() != height)
    throw std::runtime_error(fmt::format("its image is {}x{}, expected {}x{} (the G-buffer's size)", image.width(),
                                         image.height(), width, height));
  if (image.channels() < 3)
    throw std::runtime_error(fmt::format("its image has {} channel{}, expected R, G and B", image.channels(),
                                         image.channels() == 1 ? "" : "s"));
  Image rgb(width, height, 3);
  for (size_t pixel = 0; pixel < image.pixel_count(); ++pixel) {
    for (int c = 0; c < 3; ++c) {
      const float value = image.at(pixel, c);
      if (!std::isfinite(value) || value < 0.0f) {
        throw std::runtime_error(fmt::format("its image's pixel ({}, {}) channel {} is {}: expected finite E_c >= 0 W/m^2",
                                             pixel % width, pixel / width, "RGB"[c], value));
      }
      rgb.at(pixel, c) = value;
    }
  }
  return rgb;
}

namespace {

void require_number(const nlohmann::json& value, const std::string& key) {
  if (!value.is_number() || !std::isfinite(value.get<double>()) || value.get<double>() < 0.0)
    throw std::runtime_error(fmt::format("its statistics' {} is {}: expected a finite number >= 0", key, value.dump()));
}

}  // namespace

std::optional<nlohmann::json> read_program_statistics(const std::string& path) {
  if (!std::filesystem::exists(path)) return std::nullopt;
  nlohmann::json statistics;
  try {
    statistics = nlohmann::json::parse(read_text(path));
  } catch (const std::exception& error) {
    throw std::runtime_error(fmt::format("its statistics file {} is not JSON ({})", path, error.what()));
  }
  if (!statistics.is_object()) throw std::runtime_error(fmt::format("its statistics file {} is not a JSON object", path));
  for (const auto& [key, value] : statistics.items()) {
    if (key == "time_ms") {
      require_number(value, key);
    } else if (key == "timings_ms" || key == "counters") {
      if (!value.is_object()) throw std::runtime_error(fmt::format("its statistics' {} is not an object of numbers", key));
      for (const auto& [name, number] : value.items()) require_number(number, key + "." + name);
    } else {
      throw std::runtime_error(
          fmt::format("its statistics file {} has an unknown key '{}': expected time_ms, timings_ms, counters", path, key));
    }
  }
  return statistics;
}

}  // namespace causticbench
