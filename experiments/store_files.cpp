#include "experiments/store_files.h"

#include <fstream>
#include <sstream>
#include <stdexcept>

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <fmt/format.h>

#include "core/hash.h"

namespace causticbench {

std::string encode_exr(const Image& image, const std::vector<std::string>& channel_names) {
  OIIO::ImageSpec spec(image.width(), image.height(), image.channels(), OIIO::TypeDesc::FLOAT);
  if (!channel_names.empty()) spec.channelnames = channel_names;
  spec.attribute("compression", "zip");
  spec.attribute("DateTime", "");  // as write_exr: no time of writing in the file
  std::vector<unsigned char> buffer;
  OIIO::Filesystem::IOVecOutput output_proxy(buffer);
  auto output = OIIO::ImageOutput::create("image.exr");
  if (!output) throw std::runtime_error(fmt::format("no EXR writer: {}", OIIO::geterror()));
  output->set_ioproxy(&output_proxy);
  if (!output->open("image.exr", spec) || !output->write_image(OIIO::TypeDesc::FLOAT, image.data()) || !output->close()) {
    throw std::runtime_error(fmt::format("cannot encode an EXR image: {}", output->geterror()));
  }
  return std::string(buffer.begin(), buffer.end());
}

Image decode_exr(const std::string& bytes, const std::string& path) {
  OIIO::Filesystem::IOMemReader input_proxy(bytes.data(), bytes.size());
  auto input = OIIO::ImageInput::open("image.exr", nullptr, &input_proxy);
  if (!input) throw std::runtime_error(fmt::format("{}: not a readable EXR image: {}", path, OIIO::geterror()));
  const OIIO::ImageSpec& spec = input->spec();
  Image image(spec.width, spec.height, spec.nchannels);
  if (!input->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, image.data())) {
    throw std::runtime_error(fmt::format("{}: cannot read the EXR image: {}", path, input->geterror()));
  }
  return image;
}

nlohmann::json content_checksum(std::string_view bytes) {
  return {{"bytes", bytes.size()}, {"xxhash", hash_bytes(bytes.data(), bytes.size())}};
}

std::string checksum_problem(const nlohmann::json& checksum, std::string_view bytes) {
  if (!checksum.is_object() || !checksum.contains("bytes") || !checksum["bytes"].is_number_unsigned() ||
      !checksum.contains("xxhash") || !checksum["xxhash"].is_string()) {
    return "its checksum entry is not {\"bytes\": n, \"xxhash\": \"...\"}";
  }
  if (checksum["bytes"].get<uint64_t>() != bytes.size()) {
    return fmt::format("{} bytes where its record says {} (truncated or replaced)", bytes.size(),
                       checksum["bytes"].get<uint64_t>());
  }
  if (checksum["xxhash"].get<std::string>() != hash_bytes(bytes.data(), bytes.size())) {
    return "its content does not match the checksum in its record (damaged or replaced)";
  }
  return "";
}

std::optional<std::string> read_file_bytes(const std::string& path) {
  std::ifstream stream(path, std::ios::binary);
  if (!stream) return std::nullopt;
  std::stringstream buffer;
  buffer << stream.rdbuf();
  if (stream.bad()) return std::nullopt;
  return buffer.str();
}

}  // namespace causticbench
