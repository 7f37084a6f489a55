#include "methods/external/program_output.h"

#include <cmath>
#include <filesystem>

#include <fmt/format.h>

#include "core/errors.h"
#include "core/files.h"

namespace causticbench {

double program_image_most_bytes(int width, int height) {
  return 1024.0 * 1024.0 + static_cast<double>(width) * height * kProgramImageMostChannels * 4.0;
}

Image read_program_image(const std::string& path, int width, int height) {
  if (!std::filesystem::is_regular_file(path)) throw std::runtime_error(fmt::format("it wrote no image at {}", path));
  // Its size, then its header, before its pixels: the memory a program's file may make causticbench take is
  // bounded by the G-buffer's size, whatever the file claims or holds.
  const double most_bytes = program_image_most_bytes(width, height);
  std::error_code error_code;
  const double bytes = static_cast<double>(std::filesystem::file_size(path, error_code));
  if (error_code) throw std::runtime_error(fmt::format("its image {} cannot be read: {}", path, error_code.message()));
  if (bytes > most_bytes)
    throw std::runtime_error(fmt::format("its image is {:.0f} bytes, more than an EXR of {}x{} with at most {} channels "
                                         "of 32-bit floats can be ({:.0f} bytes); it is not read",
                                         bytes, width, height, kProgramImageMostChannels, most_bytes));
  std::string file;
  try {
    file = read_text(path, "an EXR image", static_cast<uintmax_t>(most_bytes));
  } catch (const InputError& error) {
    throw std::runtime_error(fmt::format("its image cannot be read ({})", error.what()));
  }
  Image image;
  try {
    image = decode_exr_checked(file, path, [&](const ExrShape& shape) {
      if (shape.width != width || shape.height != height)
        throw std::invalid_argument(fmt::format("its image is {}x{}, expected {}x{} (the G-buffer's size)", shape.width,
                                                shape.height, width, height));
      if (shape.channels < 3)
        throw std::invalid_argument(fmt::format("its image has {} channel{}, expected R, G and B", shape.channels,
                                                shape.channels == 1 ? "" : "s"));
      if (shape.channels > kProgramImageMostChannels)
        throw std::invalid_argument(fmt::format("its image has {} channels, expected R, G, B and at most {} in all",
                                                shape.channels, kProgramImageMostChannels));
    });
  } catch (const std::invalid_argument& refused) {
    throw std::runtime_error(refused.what());
  } catch (const std::exception& error) {
    throw std::runtime_error(fmt::format("its image is not a readable EXR ({})", error.what()));
  }
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
  std::string text;
  try {
    text = read_text(path, "a statistics file (JSON)", kProgramStatisticsMostBytes);
  } catch (const InputError& error) {  // a folder, or too large
    throw std::runtime_error(fmt::format("its statistics file {}", error.what()));
  }
  nlohmann::json statistics;
  try {
    statistics = nlohmann::json::parse(text);
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
