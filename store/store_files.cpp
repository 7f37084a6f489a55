#include "store/store_files.h"

#include <fstream>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

#include "core/hash.h"

namespace causticbench {

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
