#include "core/image.h"

#include <cerrno>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <fmt/format.h>

#include "core/files.h"

namespace causticbench {

namespace {

// The file of an image as OpenImageIO writes it for `format_name` ("image.exr", "image.png"), in memory.
std::string encode_with_oiio(const std::string& format_name, const OIIO::ImageSpec& spec, OIIO::TypeDesc type,
                             const void* data) {
  std::vector<unsigned char> buffer;
  OIIO::Filesystem::IOVecOutput output_proxy(buffer);
  auto output = OIIO::ImageOutput::create(format_name);
  if (!output) throw std::runtime_error(fmt::format("no image writer for {}: {}", format_name, OIIO::geterror()));
  output->set_ioproxy(&output_proxy);
  if (!output->open(format_name, spec) || !output->write_image(type, data) || !output->close()) {
    throw std::runtime_error(fmt::format("cannot encode {}: {}", format_name, output->geterror()));
  }
  return std::string(buffer.begin(), buffer.end());
}

float linear_to_srgb(float value) {
  value = std::clamp(value, 0.0f, 1.0f);
  return value <= 0.0031308f ? 12.92f * value : 1.055f * std::pow(value, 1.0f / 2.4f) - 0.055f;
}

}  // namespace

std::string encode_exr(const Image& image, const std::vector<std::string>& channel_names) {
  OIIO::ImageSpec spec(image.width(), image.height(), image.channels(), OIIO::TypeDesc::FLOAT);
  if (!channel_names.empty()) spec.channelnames = channel_names;
  spec.attribute("compression", "zip");
  // OpenImageIO's EXR writer stamps the time of writing into the capDate header unless DateTime is
  // set; set empty, capDate is written empty, so that the same pixels always give the same file.
  spec.attribute("DateTime", "");
  return encode_with_oiio("image.exr", spec, OIIO::TypeDesc::FLOAT, image.data());
}

Image decode_exr(const std::string& bytes, const std::string& path, std::vector<std::string>* channel_names) {
  return decode_exr_checked(bytes, path, {}, channel_names);
}

Image decode_exr_checked(const std::string& bytes, const std::string& path, const std::function<void(const ExrShape&)>& check,
                         std::vector<std::string>* channel_names) {
  OIIO::Filesystem::IOMemReader input_proxy(bytes.data(), bytes.size());
  auto input = OIIO::ImageInput::open("image.exr", nullptr, &input_proxy);
  if (!input) throw std::runtime_error(fmt::format("{}: not a readable EXR image: {}", path, OIIO::geterror()));
  const OIIO::ImageSpec& spec = input->spec();
  if (check) check(ExrShape{spec.width, spec.height, spec.nchannels});
  Image image(spec.width, spec.height, spec.nchannels);
  if (!input->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, image.data())) {
    throw std::runtime_error(fmt::format("{}: cannot read the EXR image: {}", path, input->geterror()));
  }
  if (channel_names) *channel_names = spec.channelnames;
  return image;
}

void write_exr(const Image& image, const std::string& path, const std::vector<std::string>& channel_names) {
  write_file_atomically(path, encode_exr(image, channel_names));
}

Image read_exr(const std::string& path, std::vector<std::string>* channel_names) {
  std::ifstream stream(path, std::ios::binary);
  if (!stream) throw std::runtime_error(fmt::format("{}: cannot open image: {}", path, os_error_text(errno)));
  std::stringstream bytes;
  bytes << stream.rdbuf();
  return decode_exr(bytes.str(), path, channel_names);
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
  write_file_atomically(path, encode_with_oiio("image.png", spec, OIIO::TypeDesc::UINT8, bytes.data()));
}

}  // namespace causticbench
