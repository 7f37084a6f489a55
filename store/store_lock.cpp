#include "store/store_lock.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <condition_variable>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <random>
#include <set>
#include <sstream>
#include <thread>

#include <fmt/format.h>

#include "core/files.h"

namespace causticbench {

namespace fs = std::filesystem;

double lock_stale_seconds() {
  const char* text = std::getenv("CAUSTICBENCH_LOCK_STALE_SECONDS");
  if (text) {
    char* end = nullptr;
    double seconds = std::strtod(text, &end);
    if (end != text && *end == '\0' && seconds > 0.0) return seconds;
  }
  return 120.0;
}

namespace {

// The kernel's start time of a process in clock ticks since boot (field 22 of /proc/PID/stat), which
// tells a process from a later one that got the same pid; "" when there is no such process.
std::string process_start(pid_t pid) {
  std::ifstream stream(fmt::format("/proc/{}/stat", pid));
  std::string text((std::istreambuf_iterator<char>(stream)), std::istreambuf_iterator<char>());
  size_t paren = text.rfind(')');
  if (paren == std::string::npos) return "";
  std::istringstream fields(text.substr(paren + 1));
  std::string field;
  for (int index = 3; index <= 22 && (fields >> field); ++index) {
    if (index == 22) return field;
  }
  return "";
}

std::string new_holder_line() {
  std::random_device device;
  uint64_t token = (static_cast<uint64_t>(device()) << 32) ^ device();
  return fmt::format("pid {} on {} started {} token {:016x}\n", getpid(), host_name(), process_start(getpid()), token);
}

struct Holder {
  long pid = 0;
  std::string host, start;
  bool parsed = false;
};

Holder parse_holder(const std::string& line) {
  Holder holder;
  std::istringstream words(line);
  std::string pid_word, on_word, started_word;
  if (words >> pid_word >> holder.pid >> on_word >> holder.host >> started_word >> holder.start) {
    holder.parsed = pid_word == "pid" && on_word == "on" && started_word == "started";
  }
  return holder;
}

std::optional<std::string> read_lock_text(const std::string& path) {
  std::ifstream stream(path);
  if (!stream) return std::nullopt;
  return std::string((std::istreambuf_iterator<char>(stream)), std::istreambuf_iterator<char>());
}

std::string first_line(const std::string& text) {
  std::string line = text.substr(0, text.find('\n'));
  return line.empty() ? "another process" : line.substr(0, line.find(" started "));
}

// Creates `path` holding `content`, unless it exists. link(2) of a complete temporary file is atomic on
// NFS (open(O_EXCL) is only from NFSv3 on, and would show a reader an empty file for a moment); a link
// whose reply was lost shows as EEXIST with the temporary file's link count at 2. Filesystems without
// hard links fall back to O_EXCL.
bool create_exclusive(const std::string& path, const std::string& content) {
  make_folders(fs::path(path).parent_path().string());
  std::string temporary = fmt::format("{}.{}.{}.tmp", path, host_name(), getpid());
  int file = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  bool written = file >= 0 && ::write(file, content.data(), content.size()) == static_cast<ssize_t>(content.size());
  int write_error = errno;
  if (file >= 0 && ::close(file) != 0 && written) {
    written = false;
    write_error = errno;
  }
  if (!written) {
    ::unlink(temporary.c_str());
    throw WriteError(fmt::format("cannot write {} (a lock file): {}", temporary, os_error_text(write_error)));
  }
  bool created = ::link(temporary.c_str(), path.c_str()) == 0;
  int error_number = errno;
  if (!created && error_number == EEXIST) {
    struct stat status {};
    created = ::stat(temporary.c_str(), &status) == 0 && status.st_nlink == 2;
  } else if (!created && (error_number == EPERM || error_number == ENOTSUP || error_number == EXDEV)) {
    int descriptor = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    error_number = errno;
    if (descriptor >= 0) {
      created = ::write(descriptor, content.data(), content.size()) == static_cast<ssize_t>(content.size());
      ::close(descriptor);
    }
  }
  ::unlink(temporary.c_str());
  if (!created && error_number != EEXIST) {
    throw WriteError(fmt::format("cannot create the lock file {}: {}", path, os_error_text(error_number)));
  }
  return created;
}

// The file server's present time: the modification time of a file just created in `folder`.
std::optional<struct timespec> filesystem_now(const std::string& folder) {
  std::string probe = fmt::format("{}/.clock.{}.{}", folder, host_name(), getpid());
  int descriptor = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (descriptor < 0) return std::nullopt;
  ::futimens(descriptor, nullptr);
  struct stat status {};
  bool known = ::fstat(descriptor, &status) == 0;
  ::close(descriptor);
  ::unlink(probe.c_str());
  if (!known) return std::nullopt;
  return status.st_mtim;
}

double seconds_between(const struct timespec& earlier, const struct timespec& later) {
  return static_cast<double>(later.tv_sec - earlier.tv_sec) + 1e-9 * static_cast<double>(later.tv_nsec - earlier.tv_nsec);
}

// Why the lock file `path` (holding `content`, last refreshed at `modified`) is stale, or "" when its
// holder may be alive.
std::string stale_reason(const std::string& path, const std::string& content, const struct timespec& modified) {
  Holder holder = parse_holder(content);
  if (holder.parsed && holder.host == host_name()) {
    std::string start = process_start(static_cast<pid_t>(holder.pid));
    if (start.empty()) return fmt::format("process {} no longer exists on this host", holder.pid);
    if (start != holder.start) return fmt::format("pid {} now belongs to another process", holder.pid);
    return "";
  }
  std::optional<struct timespec> now = filesystem_now(fs::path(path).parent_path().string());
  if (!now) return "";
  double age = seconds_between(modified, *now);
  if (age > lock_stale_seconds()) return fmt::format("no heartbeat for {:.0f} s", age);
  return "";
}

// Refreshes the modification time of every lock this process holds, so that other hosts see it alive.
class Heartbeat {
 public:
  ~Heartbeat() {
    {
      std::lock_guard<std::mutex> guard(mutex_);
      stopping_ = true;
    }
    wake_.notify_all();
    if (thread_.joinable()) thread_.join();
  }
  void add(const std::string& path) {
    std::lock_guard<std::mutex> guard(mutex_);
    held_.insert(path);
    if (!thread_.joinable()) thread_ = std::thread([this] { beat(); });
  }
  void remove(const std::string& path) {
    std::lock_guard<std::mutex> guard(mutex_);
    held_.erase(path);
  }

 private:
  void beat() {
    const auto interval = std::chrono::duration<double>(lock_stale_seconds() / 8.0);
    std::unique_lock<std::mutex> guard(mutex_);
    while (!wake_.wait_for(guard, interval, [this] { return stopping_; })) {
      for (const std::string& path : held_) ::utimensat(AT_FDCWD, path.c_str(), nullptr, 0);
    }
  }
  std::mutex mutex_;
  std::condition_variable wake_;
  std::set<std::string> held_;
  bool stopping_ = false;
  std::thread thread_;
};

Heartbeat& heartbeat() {
  static Heartbeat instance;
  return instance;
}

// Removes the stale lock `path`, found holding `content`, unless it changed meanwhile.
void break_stale_lock(const std::string& path, const std::string& content, const std::string& reason) {
  const std::string breaker = path + ".break";
  if (!create_exclusive(breaker, new_holder_line())) {
    // Another process is removing it; or one died doing so, leaving its .break, which is stale in turn.
    struct stat status {};
    std::optional<std::string> breaker_content = read_lock_text(breaker);
    if (breaker_content && ::stat(breaker.c_str(), &status) == 0 &&
        !stale_reason(breaker, *breaker_content, status.st_mtim).empty()) {
      ::unlink(breaker.c_str());
    }
    return;
  }
  if (read_lock_text(path) == content) {
    fmt::print(stderr, "warning: removing the stale lock {} of {} ({})\n", path, first_line(content), reason);
    ::unlink(path.c_str());
  }
  ::unlink(breaker.c_str());
}

}  // namespace

StoreLock::StoreLock(std::string path, std::string holder) : path_(std::move(path)), holder_(std::move(holder)) {
  heartbeat().add(path_);
}

std::optional<StoreLock> StoreLock::try_acquire(const std::string& path) {
  // A few attempts: the file may vanish between a failed creation and the look at its holder, or be stale.
  for (int attempt = 0; attempt < 4; ++attempt) {
    std::string holder = new_holder_line();
    if (create_exclusive(path, holder)) return StoreLock(path, holder);
    std::optional<std::string> content = read_lock_text(path);
    struct stat status {};
    if (!content || ::stat(path.c_str(), &status) != 0) continue;  // released meanwhile
    std::string reason = stale_reason(path, *content, status.st_mtim);
    if (reason.empty()) return std::nullopt;
    break_stale_lock(path, *content, reason);
  }
  return std::nullopt;
}

StoreLock StoreLock::acquire(const std::string& path, const std::string& what) {
  if (std::optional<StoreLock> lock_now = try_acquire(path)) return std::move(*lock_now);
  std::optional<std::string> content = read_lock_text(path);
  fmt::print(stderr, "waiting for {}: {} holds it (lock {})\n", what, first_line(content.value_or("")), path);
  // Polling: no file system event reaches other NFS clients. From 20 ms up to 1 s between looks.
  auto pause = std::chrono::milliseconds(20);
  while (true) {
    std::this_thread::sleep_for(pause);
    if (std::optional<StoreLock> lock_now = try_acquire(path)) return std::move(*lock_now);
    pause = std::min(pause * 2, std::chrono::milliseconds(1000));
  }
}

StoreLock::StoreLock(StoreLock&& other) noexcept : path_(std::move(other.path_)), holder_(std::move(other.holder_)) {
  other.path_.clear();
}

StoreLock& StoreLock::operator=(StoreLock&& other) noexcept {
  if (this != &other) {
    release();
    path_ = std::move(other.path_);
    holder_ = std::move(other.holder_);
    other.path_.clear();
  }
  return *this;
}

StoreLock::~StoreLock() { release(); }

void StoreLock::release() {
  if (path_.empty()) return;
  heartbeat().remove(path_);
  // Only while it is still this process's: a lock taken over as stale (a frozen holder) is the new one's.
  if (read_lock_text(path_) == holder_) ::unlink(path_.c_str());
  path_.clear();
}

}  // namespace causticbench
