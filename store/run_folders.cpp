#include "store/run_folders.h"

#include <filesystem>

#include <fmt/format.h>

#include "core/files.h"
#include "core/hash.h"
#include "core/staging_folder.h"
#include "store/record_check.h"
#include "store/store_files.h"

namespace causticbench {

namespace fs = std::filesystem;

bool measured_against_other_reference(const nlohmann::json& record, const std::string& current_reference_key) {
  const auto found = record.find("reference_key");
  if (found == record.end() || !found->is_string() || found->get<std::string>().empty()) return false;
  return !current_reference_key.empty() && found->get<std::string>() != current_reference_key;
}

StoredRun inspect_stored_run(const std::string& run_folder) {
  StoredRun stored;
  const std::string path = (fs::path(run_folder) / "record.json").string();
  std::error_code error;
  if (!fs::exists(run_folder, error)) return stored;
  stored.state = StoredRun::State::damaged;
  std::optional<std::string> text = read_file_bytes(path);
  if (!text) {
    stored.problem = fmt::format("{}: missing or unreadable", path);
    return stored;
  }
  nlohmann::json record = nlohmann::json::parse(*text, nullptr, /*allow_exceptions=*/false);
  std::string problem = record.is_discarded() ? "not valid JSON (truncated?)" : run_record_problem(record, run_folder);
  if (!problem.empty()) {
    stored.problem = fmt::format("{}: {}", path, problem);
    return stored;
  }
  stored.state = StoredRun::State::stored;
  stored.record = std::move(record);
  stored.record_hash = hash_text(*text);
  return stored;
}

bool run_is_stored(const std::string& run_folder) {
  return inspect_stored_run(run_folder).state == StoredRun::State::stored;
}

void store_run_folder(const std::string& run_folder, const std::vector<std::pair<std::string, std::string>>& images,
                      nlohmann::json record) {
  StagingFolder staging(run_folder);
  nlohmann::json checksums = nlohmann::json::object();
  for (const auto& [name, bytes] : images) {
    write_file_atomically((fs::path(staging.path()) / name).string(), bytes);
    checksums[name] = content_checksum(bytes);
  }
  record["images"] = checksums;
  // The record last: a folder is a run only with it, and it names what the images must be.
  // A message that is not UTF-8 (a program's stderr in an error) is stored with U+FFFD where it is not,
  // rather than lose the run.
  write_text_atomically((fs::path(staging.path()) / "record.json").string(),
                        record.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
  staging.commit();
}

}  // namespace causticbench
