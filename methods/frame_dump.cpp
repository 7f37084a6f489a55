#include "methods/frame_dump.h"

#include <cstdio>
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
