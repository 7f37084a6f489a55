// Content hashes for keys (runs, references, builds): 16 hex digits of xxHash64.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

namespace causticbench {

std::string hash_text(const std::string& text);
// Of the canonical (key-sorted, compact) JSON dump: the same for any key order in the source.
std::string hash_json(const nlohmann::json& value);
// Of raw bytes (mesh vertices and the like).
std::string hash_bytes(const void* data, size_t size);
// Of a file's content, read in blocks (the same value as hash_bytes of the whole content); its size in
// `bytes`. Throws std::runtime_error naming the file when it cannot be read.
std::string hash_file(const std::string& path, uint64_t& bytes);

}  // namespace causticbench
