// The files of the results store as bytes: EXR images encoded in memory (core/image.h), so that the checksum a record
// keeps is of exactly the bytes that core/files.h's write_file_atomically() writes (and reports the OS
// error of); checksums; reading back. A stored image is read once into memory, checked against its
// checksum, and decoded from those same bytes: a file replaced between the check and the read cannot
// slip through.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/image.h"

namespace causticbench {

// {"bytes": size, "xxhash": "<16 hex digits>"}: how records name the content of a file they refer to.
nlohmann::json content_checksum(std::string_view bytes);
// "" when `bytes` matches `checksum` (a content_checksum() object), otherwise what differs.
std::string checksum_problem(const nlohmann::json& checksum, std::string_view bytes);

// The whole file, or std::nullopt when it does not exist or cannot be read.
std::optional<std::string> read_file_bytes(const std::string& path);

}  // namespace causticbench
