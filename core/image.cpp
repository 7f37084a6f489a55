#include "core/image.h"

#include <filesystem>
#include <stdexcept>

#include <OpenImageIO/imageio.h>
#include <fmt/format.h>

namespace causticbench {

namespace {

void write_with_oiio(const std::string& path, const OIIO::ImageSpec& spec, OIIO::TypeDesc type, const void* data) {
  std::string temporary = path + ".partial" + std::filesystem::path(path).extension().string();
  auto output = OIIO::ImageOutput::create(path);
  if (!output) throw std::runtime_error(fmt::format("{}: no image writer: {}", path, OIIO::geterror()));
  if (!output->open(temporary, spec) || !output->write_image(type, data)) {
    throw std::runtime_error(fmt::format("{}: cannot write image: {}", path, output->geterror()));
  }
  output->close();
  std::filesystem::rename(temporary, path);
}

float linear_to_srgb(float value) {
  value = std::clamp(value, 0.0f, 1.0f);
  return value <= 0.0031308f ? 12.92f * value : 1.055f * std::pow(value, 1.0f / 2.4f) - 0.055f;
}

}  // namespace

void write_exr(const Image& image, const std::string& path, const std::vector<std::string>& channel_names) {
  OIIO::ImageSpec spec(image.width(), image.height(), image.channels(), OIIO::TypeDesc::FLOAT);
  if (!channel_names.empty()) spec.channelnames = channel_names;
  spec.attribute("compression", "zip");
  // OpenImageIO's EXR writer stamps the time of writing into the capDate header unless DateTime is
  // set; set empty, capDate is written empty, so that the same pixels always give the same file.
  spec.attribute("DateTime", "");
  write_with_oiio(path, spec, OIIO::TypeDesc::FLOAT, image.data());
}

Image read_exr(const std::string& path) {
  auto input = OIIO::ImageInput::open(path);
  if (!input) throw std::runtime_error(fmt::format("{}: cannot open image: {}", path, OIIO::geterror()));
  const OIIO::ImageSpec& spec = input->spec();
  Image image(spec.width, spec.height, spec.nchannels);
  if (!input->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, image.data())) {
    throw std::runtime_error(fmt::format("{}: cannot read image: {}", path, input->geterror()));
  }
  return image;
}

void write_png(const Image& image, const std::string& path, float exposure) {
  std::vector<unsigned char> bytes(image.pixel_count() * 3);
  for (size_t pixel = 0; pixel < image.pixel_count(); ++pixel) {
    for (int c = 0; c < 3; ++c) {
      float value = image.at(pixel, std::min(c, image.channels() - 1)) * exposure;
      if (!std::isfinite(value)) value = 0.0f;
      bytes[pixel * 3 + c] = static_cast<unsigned char>(std::lround(linear_to_srgb(value) * 255.0f));
    }
  }
  OIIO::ImageSpec spec(image.width(), image.height(), 3, OIIO::TypeDesc::UINT8);
  write_with_oiio(path, spec, OIIO::TypeDesc::UINT8, bytes.data());
}

}  // namespace causticbench
