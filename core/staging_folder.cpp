#include "core/staging_folder.h"

#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdint>
#include <filesystem>

#include <fmt/format.h>

namespace causticbench {

namespace fs = std::filesystem;

namespace {

std::string host_name() {
  char name[256] = {};
  gethostname(name, sizeof(name) - 1);
  return name;
}

const char* kStagingPrefix = ".partial-";

}  // namespace

StagingFolder::StagingFolder(std::string final_path) : final_(std::move(final_path)) {
  fs::path final_path_fs(final_);
  // Unique per process and per folder within it (threads of one process may stage the same path).
  static std::atomic<uint64_t> counter{0};
  staging_ = (final_path_fs.parent_path() / fmt::format("{}{}-{}-{}.{}", kStagingPrefix, final_path_fs.filename().string(),
                                                        host_name(), getpid(), counter++))
                 .string();
  fs::remove_all(staging_);
  fs::create_directories(staging_);
}

StagingFolder::~StagingFolder() {
  if (!committed_) {
    std::error_code ignored;
    fs::remove_all(staging_, ignored);
  }
}

void StagingFolder::commit() {
  if (fs::exists(final_)) {
    std::string old = staging_ + ".old";
    fs::rename(final_, old);
    fs::rename(staging_, final_);
    fs::remove_all(old);
  } else {
    fs::rename(staging_, final_);
  }
  committed_ = true;
}

bool StagingFolder::commit_if_absent() {
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
  if (!fs::is_directory(folder)) return;
  std::string host = host_name();
  for (const auto& entry : fs::directory_iterator(folder)) {
    std::string name = entry.path().filename().string();
    if (name.rfind(kStagingPrefix, 0) != 0) continue;
    // name: .partial-<key>-<host>-<pid>.<n>[.old] (atoi stops at the '.')
    std::string rest = name.substr(std::string(kStagingPrefix).size());
    if (rest.size() > 4 && rest.compare(rest.size() - 4, 4, ".old") == 0) rest.resize(rest.size() - 4);
    size_t last = rest.rfind('-');
    if (last == std::string::npos) continue;
    std::string before = rest.substr(0, last);
    int pid = std::atoi(rest.substr(last + 1).c_str());
    bool same_host = before.size() > host.size() && before.compare(before.size() - host.size(), host.size(), host) == 0;
    if (same_host && pid > 0 && kill(pid, 0) != 0 && errno == ESRCH) fs::remove_all(entry.path());
  }
}

}  // namespace causticbench
