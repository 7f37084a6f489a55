#include "methods/frame_dump.h"

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace causticbench {

void write_dump_bytes(const std::string& path, const char* data, size_t bytes) {
  std::string temporary = path + ".partial";
  {
    std::ofstream stream(temporary, std::ios::binary | std::ios::trunc);
    if (!stream) throw std::runtime_error(path + ": cannot write");
    stream.write(data, static_cast<std::streamsize>(bytes));
    if (!stream) throw std::runtime_error(path + ": write failed");
  }
  if (std::rename(temporary.c_str(), path.c_str()) != 0) throw std::runtime_error(path + ": cannot rename");
}

void write_floats(const std::string& path, const std::vector<float>& values) {
  write_dump_bytes(path, reinterpret_cast<const char*>(values.data()), values.size() * sizeof(float));
}

std::vector<float> read_floats(const std::string& path) {
  std::ifstream stream(path, std::ios::binary | std::ios::ate);
  if (!stream) throw std::runtime_error(path + ": cannot open");
  std::streamsize bytes = stream.tellg();
  if (bytes % static_cast<std::streamsize>(sizeof(float)) != 0) {
    throw std::runtime_error(path + ": not a float32 array");
  }
  std::vector<float> values(static_cast<size_t>(bytes) / sizeof(float));
  stream.seekg(0);
  stream.read(reinterpret_cast<char*>(values.data()), bytes);
  if (!stream) throw std::runtime_error(path + ": read failed");
  return values;
}

void write_words(const std::string& path, const std::vector<uint32_t>& words) {
  write_dump_bytes(path, reinterpret_cast<const char*>(words.data()), words.size() * sizeof(uint32_t));
}

std::vector<uint32_t> read_words(const std::string& path) {
  const std::vector<float> floats = read_floats(path);
  std::vector<uint32_t> words(floats.size());
  if (!words.empty()) std::memcpy(words.data(), floats.data(), words.size() * sizeof(uint32_t));
  return words;
}

std::map<std::string, double> read_dump_fields(const std::string& path, const std::vector<std::string>& required) {
  std::ifstream stream(path);
  if (!stream) throw std::runtime_error(path + ": cannot open (not a --dump-frame folder, or another method's?)");
  std::map<std::string, double> values;
  std::string name;
  double value;
  while (stream >> name >> value) values[name] = value;
  for (const std::string& field : required)
    if (!values.count(field)) throw std::runtime_error(path + ": missing '" + field + "'");
  return values;
}

FrameDumpInfo receiver_dump_info(uint32_t width, uint32_t height, const std::vector<float>& receiver_positions,
                                 double evaluations_per_receiver) {
  FrameDumpInfo info;
  info.width = width;
  info.height = height;
  const size_t pixels = static_cast<size_t>(width) * height;
  if (receiver_positions.size() < 4 * pixels)
    throw std::runtime_error("receiver_positions.bin: " + std::to_string(receiver_positions.size() / 4) +
                             " pixels, the frame has " + std::to_string(pixels));
  info.receivers.resize(pixels);
  size_t receiver_count = 0;
  for (size_t pixel = 0; pixel < pixels; ++pixel) {
    info.receivers[pixel] = receiver_positions[4 * pixel + 3] != 0.0f;
    receiver_count += info.receivers[pixel];
  }
  info.evaluations = static_cast<double>(receiver_count) * evaluations_per_receiver;
  return info;
}

void write_dump_method(const std::string& folder, const std::string& method) {
  std::string line = method + "\n";
  write_dump_bytes(folder + "/method.txt", line.data(), line.size());
}

std::string read_dump_method(const std::string& folder) {
  std::string path = folder + "/method.txt";
  std::ifstream stream(path);
  if (!stream) {
    if (std::filesystem::is_regular_file(folder + "/frame.txt")) return "pinhole";
    throw std::runtime_error(path + ": not found (not a dump folder?); write one with `causticbench render SCENE "
                             "--method METHOD --out OUT --dump-frame " + folder + "`");
  }
  std::string method;
  std::getline(stream, method);
  while (!method.empty() && (method.back() == '\r' || method.back() == ' ' || method.back() == '\t')) method.pop_back();
  if (method.empty()) throw std::runtime_error(path + ": empty; expected the name of the method that wrote the dump");
  return method;
}

std::string json_quoted(const std::string& text) {
  std::string quoted = "\"";
  for (char character : text) {
    unsigned char code = static_cast<unsigned char>(character);
    if (character == '"' || character == '\\') {
      quoted += '\\';
      quoted += character;
    } else if (code < 0x20) {
      char escape[8];
      std::snprintf(escape, sizeof escape, "\\u%04x", code);
      quoted += escape;
    } else {
      quoted += character;
    }
  }
  return quoted + "\"";
}

FrameReplay::~FrameReplay() = default;

std::string FrameReplay::facts_json() const { return ""; }

}  // namespace causticbench
