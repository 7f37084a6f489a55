#include "core/files.h"

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <unistd.h>

#include <fmt/format.h>

#include "core/errors.h"

namespace causticbench {

void write_text_atomically(const std::string& path, const std::string& text) {
  std::string temporary = fmt::format("{}.partial.{}", path, getpid());
  {
    std::ofstream stream(temporary, std::ios::binary | std::ios::trunc);
    if (!stream) throw std::runtime_error(fmt::format("{}: cannot write", temporary));
    stream << text;
    stream.flush();
    if (!stream) throw std::runtime_error(fmt::format("{}: write failed", temporary));
  }
  std::filesystem::rename(temporary, path);
}

std::string read_text(const std::string& path) {
  if (!std::filesystem::exists(path)) throw InputError(fmt::format("{}: file not found", path));
  std::ifstream stream(path, std::ios::binary);
  if (!stream) throw InputError(fmt::format("{}: cannot open file for reading", path));
  std::stringstream buffer;
  buffer << stream.rdbuf();
  return buffer.str();
}

void ensure_folder(const std::string& path) {
  std::error_code error;
  if (std::filesystem::exists(path) && !std::filesystem::is_directory(path)) {
    throw InputError(fmt::format("{}: expected an output folder, found an existing file", path));
  }
  std::filesystem::create_directories(path, error);
  if (error) throw InputError(fmt::format("{}: cannot create the output folder: {}", path, error.message()));
}

}  // namespace causticbench
