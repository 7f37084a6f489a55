#include "core/staging_folder.h"

#include <fcntl.h>
#include <stdio.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdint>
#include <filesystem>
#include <map>

#include <fmt/format.h>

#include "core/files.h"

namespace causticbench {

namespace fs = std::filesystem;

namespace {

const char* kStagingPrefix = ".partial-";
const char* kOldSuffix = ".old";

[[noreturn]] void throw_rename_error(const std::string& from, const std::string& to, int error_number) {
  throw WriteError(fmt::format("cannot rename {} to {}: {}", from, to, os_error_text(error_number)));
}

// A commit step of the fault injection: a kill, or a failure as an I/O error.
void commit_step(const std::string& description) {
  InjectedFault fault = next_write_step(description);
  if (fault == InjectedFault::kill) kill_this_process();
  if (fault == InjectedFault::fail) throw WriteError(fmt::format("cannot {}: {}", description, os_error_text(EIO)));
}

// After a replacement: the old copy goes. A failure to remove it leaves it to remove_stale_staging()
// once this process has ended; the commit itself has happened.
void discard(const std::string& old) {
  InjectedFault fault = next_write_step("discard " + old);
  if (fault == InjectedFault::kill) kill_this_process();
  std::error_code ignored;
  if (fault == InjectedFault::none) fs::remove_all(old, ignored);
}

bool exchange_unsupported(int error_number) {
  return error_number == EINVAL || error_number == ENOSYS || error_number == ENOTSUP || error_number == EOPNOTSUPP;
}

}  // namespace

StagingFolder::StagingFolder(std::string final_path) : final_(std::move(final_path)) {
  fs::path final_path_fs(final_);
  // Unique per process and per folder within it (threads of one process may stage the same path).
  static std::atomic<uint64_t> counter{0};
  staging_ = (final_path_fs.parent_path() / fmt::format("{}{}-{}-{}.{}", kStagingPrefix, final_path_fs.filename().string(),
                                                        host_name(), getpid(), counter++))
                 .string();
  std::error_code ignored;
  fs::remove_all(staging_, ignored);
  make_folders(staging_);
}

StagingFolder::~StagingFolder() {
  if (!committed_) {
    std::error_code ignored;
    fs::remove_all(staging_, ignored);
  }
}

void StagingFolder::commit() {
  commit_step("commit " + final_);
  if (!fs::exists(final_)) {
    if (std::rename(staging_.c_str(), final_.c_str()) != 0) throw_rename_error(staging_, final_, errno);
    committed_ = true;
    return;
  }
  if (!fault_injection_option("no_rename_exchange")) {
    if (renameat2(AT_FDCWD, staging_.c_str(), AT_FDCWD, final_.c_str(), RENAME_EXCHANGE) == 0) {
      committed_ = true;
      discard(staging_);  // the old copy, now under the staging name
      return;
    }
    if (!exchange_unsupported(errno)) throw_rename_error(staging_, final_, errno);
  }
  // Two renames; between them the final name is free and <staging>.old marks the staging folder as
  // complete, which is what remove_stale_staging() recovers by.
  const std::string old = staging_ + kOldSuffix;
  if (std::rename(final_.c_str(), old.c_str()) != 0) throw_rename_error(final_, old, errno);
  try {
    commit_step("replace " + final_);
    if (std::rename(staging_.c_str(), final_.c_str()) != 0) throw_rename_error(staging_, final_, errno);
  } catch (const WriteError&) {
    std::rename(old.c_str(), final_.c_str());  // the old copy back in place
    throw;
  }
  committed_ = true;
  discard(old);
}

bool StagingFolder::commit_if_absent() {
  commit_step("commit " + final_);
  std::error_code error;
  // rename(2) onto an existing non-empty folder fails (ENOTEMPTY or EEXIST): the first one wins.
  if (!fs::exists(final_)) fs::rename(staging_, final_, error);
  if (fs::exists(final_) && !fs::exists(staging_)) {
    committed_ = true;
    return true;
  }
  return false;  // the destructor removes our copy
}

void remove_stale_staging(const std::string& folder) {
  std::error_code error;
  if (!fs::is_directory(folder, error)) return;
  const std::string host = host_name();
  // Staging name (without .old) -> the final folder's name, for every staging folder of a dead process.
  std::map<std::string, std::string> stale;
  for (fs::directory_iterator it(folder, error), end; !error && it != end; it.increment(error)) {
    std::string name = it->path().filename().string();
    if (name.rfind(kStagingPrefix, 0) != 0) continue;
    // name: .partial-<final>-<host>-<pid>.<n>[.old] (atoi stops at the '.')
    std::string base = name;
    if (base.size() > 4 && base.compare(base.size() - 4, 4, kOldSuffix) == 0) base.resize(base.size() - 4);
    std::string rest = base.substr(std::string(kStagingPrefix).size());
    size_t last = rest.rfind('-');
    if (last == std::string::npos) continue;
    std::string before = rest.substr(0, last);
    int pid = std::atoi(rest.substr(last + 1).c_str());
    bool same_host = before.size() > host.size() + 1 && before.compare(before.size() - host.size(), host.size(), host) == 0 &&
                     before[before.size() - host.size() - 1] == '-';
    if (same_host && pid > 0 && !process_exists(pid)) stale[base] = before.substr(0, before.size() - host.size() - 1);
  }
  for (const auto& [base, final_name] : stale) {
    fs::path staging = fs::path(folder) / base, old = fs::path(folder) / (base + kOldSuffix), final = fs::path(folder) / final_name;
    std::error_code ignored;
    // A replacement killed between its two renames: the new copy is complete, put it in place; with no new
    // copy, put the old one back. A rename onto a folder that another process restored meanwhile fails.
    if (fs::exists(old) && !fs::exists(final)) {
      if (fs::exists(staging)) fs::rename(staging, final, ignored);
      else fs::rename(old, final, ignored);
    }
    fs::remove_all(staging, ignored);
    fs::remove_all(old, ignored);
  }
}

}  // namespace causticbench
