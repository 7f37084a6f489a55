#include "experiments/store_lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "core/files.h"

namespace causticbench {

namespace fs = std::filesystem;

namespace {

int open_lock_file(const std::string& path) {
  make_folders(fs::path(path).parent_path().string());
  int descriptor = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0666);
  if (descriptor < 0) throw WriteError(fmt::format("cannot create the lock file {}: {}", path, os_error_text(errno)));
  return descriptor;
}

// Who holds it, for the waiting message (not part of the store's data: a plain write is enough).
void write_holder(int descriptor) {
  std::string holder = fmt::format("pid {} on {}\n", getpid(), host_name());
  if (::ftruncate(descriptor, 0) != 0) return;
  ssize_t written = ::pwrite(descriptor, holder.data(), holder.size(), 0);
  static_cast<void>(written);
}

std::string read_holder(const std::string& path) {
  std::ifstream stream(path);
  std::string line;
  std::getline(stream, line);
  return line.empty() ? "another process" : line;
}

int lock(int descriptor, int operation) {
  int result;
  do result = ::flock(descriptor, operation);
  while (result != 0 && errno == EINTR);
  return result;
}

}  // namespace

StoreLock::StoreLock(int descriptor) : descriptor_(descriptor) {}

std::optional<StoreLock> StoreLock::try_acquire(const std::string& path) {
  int descriptor = open_lock_file(path);
  if (lock(descriptor, LOCK_EX | LOCK_NB) != 0) {
    int error_number = errno;
    ::close(descriptor);
    if (error_number == EWOULDBLOCK) return std::nullopt;
    throw WriteError(fmt::format("cannot lock {}: {}", path, os_error_text(error_number)));
  }
  write_holder(descriptor);
  return StoreLock(descriptor);
}

StoreLock StoreLock::acquire(const std::string& path, const std::string& what) {
  if (std::optional<StoreLock> lock_now = try_acquire(path)) return std::move(*lock_now);
  fmt::print(stderr, "waiting for {}: {} holds it (lock {})\n", what, read_holder(path), path);
  int descriptor = open_lock_file(path);
  if (lock(descriptor, LOCK_EX) != 0) {
    int error_number = errno;
    ::close(descriptor);
    throw WriteError(fmt::format("cannot lock {}: {}", path, os_error_text(error_number)));
  }
  write_holder(descriptor);
  return StoreLock(descriptor);
}

StoreLock::StoreLock(StoreLock&& other) noexcept : descriptor_(other.descriptor_) { other.descriptor_ = -1; }

StoreLock& StoreLock::operator=(StoreLock&& other) noexcept {
  if (this != &other) {
    release();
    descriptor_ = other.descriptor_;
    other.descriptor_ = -1;
  }
  return *this;
}

StoreLock::~StoreLock() { release(); }

void StoreLock::release() {
  if (descriptor_ < 0) return;
  if (::ftruncate(descriptor_, 0) != 0) {
    // The holder line stays; it names a process that no longer holds the lock, harmless.
  }
  ::close(descriptor_);  // releases the flock
  descriptor_ = -1;
}

}  // namespace causticbench
