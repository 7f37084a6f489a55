#include "core/hash.h"

#include <cstdio>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>
#include <xxhash.h>

namespace causticbench {

std::string hash_bytes(const void* data, size_t size) {
  return fmt::format("{:016x}", static_cast<unsigned long long>(XXH64(data, size, 0)));
}

std::string hash_file(const std::string& path, uint64_t& bytes) {
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (!file) throw std::runtime_error(path + ": cannot open for reading");
  XXH64_state_t* state = XXH64_createState();
  XXH64_reset(state, 0);
  std::vector<char> block(1 << 20);
  bytes = 0;
  size_t read;
  while ((read = std::fread(block.data(), 1, block.size(), file)) > 0) {
    XXH64_update(state, block.data(), read);
    bytes += read;
  }
  bool failed = std::ferror(file) != 0;
  std::fclose(file);
  unsigned long long value = XXH64_digest(state);
  XXH64_freeState(state);
  if (failed) throw std::runtime_error(path + ": read failed");
  return fmt::format("{:016x}", value);
}

std::string hash_text(const std::string& text) { return hash_bytes(text.data(), text.size()); }

// nlohmann::json keeps object keys sorted, so the dump is canonical whatever the order in the file.
std::string hash_json(const nlohmann::json& value) { return hash_text(value.dump()); }

}  // namespace causticbench
