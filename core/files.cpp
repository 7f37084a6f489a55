#include "core/files.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include <fmt/format.h>

#include "core/errors.h"

namespace causticbench {

namespace fs = std::filesystem;

namespace {

constexpr const char* kFaultVariable = "CAUSTICBENCH_FAULT_INJECT";
constexpr const char* kPartialMarker = ".partial.";

// One item of CAUSTICBENCH_FAULT_INJECT: an action at a step number or at steps matching a text.
struct FaultRule {
  InjectedFault action = InjectedFault::none;
  long step = 0;        // > 0: that step only
  std::string pattern;  // otherwise: every step whose description contains it
};

struct FaultPlan {
  bool trace = false;
  std::vector<std::string> options;
  std::vector<FaultRule> rules;
};

std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> parts;
  std::stringstream stream(text);
  for (std::string part; std::getline(stream, part, separator);)
    if (!part.empty()) parts.push_back(part);
  return parts;
}

// Read at every step rather than once, so that a test can set the variable in its own process.
FaultPlan fault_plan() {
  FaultPlan plan;
  const char* value = std::getenv(kFaultVariable);
  if (!value || !*value) return plan;
  for (const std::string& item : split(value, ',')) {
    size_t at = item.find('@');
    if (at == std::string::npos) {
      if (item == "trace") plan.trace = true;
      else plan.options.push_back(item);
      continue;
    }
    std::string action = item.substr(0, at), where = item.substr(at + 1);
    FaultRule rule;
    if (action == "kill") rule.action = InjectedFault::kill;
    else if (action == "fail") rule.action = InjectedFault::fail;
    if (rule.action == InjectedFault::none || where.empty()) {
      throw InputError(fmt::format("{}: expected items kill@STEP, fail@STEP (a step number or a text), trace or "
                                   "no_rename_exchange, found '{}'", kFaultVariable, item));
    }
    char* end = nullptr;
    long step = std::strtol(where.c_str(), &end, 10);
    if (*end == '\0' && step > 0) rule.step = step;
    else rule.pattern = where;
    plan.rules.push_back(rule);
  }
  return plan;
}

// Removes a temporary file, and whatever a writer left under names that start with it, unless released.
class TemporaryFile {
 public:
  explicit TemporaryFile(std::string path) : path_(std::move(path)) {}
  ~TemporaryFile() {
    if (path_.empty()) return;
    std::error_code ignored, listing;
    fs::remove(path_, ignored);
    fs::path folder = fs::path(path_).parent_path();
    std::string prefix = fs::path(path_).filename().string();
    for (fs::directory_iterator it(folder.empty() ? "." : folder, listing), end; !listing && it != end; it.increment(listing)) {
      // A writer's own temporaries (OpenImageIO's <temporary>.partial.exr) are <temporary>.<more>.
      if (it->path().filename().string().rfind(prefix + ".", 0) == 0) fs::remove(it->path(), ignored);
    }
  }
  TemporaryFile(const TemporaryFile&) = delete;
  TemporaryFile& operator=(const TemporaryFile&) = delete;
  void release() { path_.clear(); }

 private:
  std::string path_;
};

// <name>.partial.<host>-<pid>.<n><extension>: unique per process and write (threads of one process may
// write the same path), owned by a process that remove_stale_partial_files() can check, and with the
// final extension, which image writers choose their format by.
std::string temporary_path(const std::string& path) {
  static std::atomic<uint64_t> counter{0};
  return fmt::format("{}{}{}-{}.{}{}", path, kPartialMarker, host_name(), getpid(), counter++,
                     fs::path(path).extension().string());
}

[[noreturn]] void throw_write_error(const std::string& path, int error_number) {
  throw WriteError(fmt::format("cannot write {}: {}", path, os_error_text(error_number)));
}

// A writer that reports no errno (an image library) failed: say so, and name a full disk when the
// folder's file system has no space left, the usual cause.
[[noreturn]] void throw_writer_error(const std::string& path, const std::string& what) {
  struct statvfs space{};
  std::string folder = fs::path(path).parent_path().string();
  bool full = statvfs(folder.empty() ? "." : folder.c_str(), &space) == 0 && space.f_bavail == 0;
  // Named once: the writer's own message often says it already, then with its symbol.
  std::string said = what;
  const std::string text = std::strerror(ENOSPC), named = os_error_text(ENOSPC);
  if (const size_t at = said.find(text); at != std::string::npos) {
    if (said.compare(at, named.size(), named) != 0) said.replace(at, text.size(), named);
    full = false;
  }
  throw WriteError(fmt::format("cannot write {}: {}{}", path, said, full ? ": " + named : ""));
}

// A write step's injected fault after half the temporary file exists: a kill, or a full disk.
void act_on_write_fault(InjectedFault fault, const std::string& path) {
  if (fault == InjectedFault::kill) kill_this_process();
  if (fault == InjectedFault::fail) throw_write_error(path, ENOSPC);
}

void write_all(int descriptor, std::string_view bytes, const std::string& path) {
  while (!bytes.empty()) {
    ssize_t written = ::write(descriptor, bytes.data(), bytes.size());
    if (written < 0 && errno == EINTR) continue;
    if (written < 0) throw_write_error(path, errno);
    bytes.remove_prefix(static_cast<size_t>(written));
  }
}

}  // namespace

std::string os_error_text(int error_number) {
  const char* name = strerrorname_np(error_number);
  return fmt::format("{} ({})", std::strerror(error_number), name ? name : std::to_string(error_number));
}

std::string host_name() {
  char name[256] = {};
  gethostname(name, sizeof(name) - 1);
  return name;
}

bool process_exists(int pid) { return pid > 0 && (kill(pid, 0) == 0 || errno != ESRCH); }

InjectedFault next_write_step(const std::string& description) {
  static std::atomic<long> steps{0};
  long step = ++steps;
  FaultPlan plan = fault_plan();
  if (plan.trace) fmt::print(stderr, "fault injection: step {}: {}\n", step, description);
  for (const FaultRule& rule : plan.rules) {
    bool match = rule.step > 0 ? rule.step == step : description.find(rule.pattern) != std::string::npos;
    if (!match) continue;
    if (plan.trace) fmt::print(stderr, "fault injection: step {}: {}\n", step, rule.action == InjectedFault::kill ? "kill" : "fail");
    return rule.action;
  }
  return InjectedFault::none;
}

void kill_this_process() {
  raise(SIGKILL);
  _exit(137);  // not reached
}

bool fault_injection_option(const std::string& option) {
  std::vector<std::string> options = fault_plan().options;
  return std::find(options.begin(), options.end(), option) != options.end();
}

void make_folders(const std::string& path) {
  std::error_code error;
  fs::create_directories(path, error);
  if (error) throw WriteError(fmt::format("cannot create the folder {}: {}", path, os_error_text(error.value())));
}

void rename_atomically(const std::string& from, const std::string& to) {
  InjectedFault fault = next_write_step("rename " + to);
  if (fault == InjectedFault::kill) kill_this_process();
  if (fault == InjectedFault::fail || std::rename(from.c_str(), to.c_str()) != 0) {
    int error_number = fault == InjectedFault::fail ? EIO : errno;
    throw WriteError(fmt::format("cannot rename {} to {}: {}", from, to, os_error_text(error_number)));
  }
}

void write_file_atomically(const std::string& path, std::string_view bytes) {
  const std::string temporary = temporary_path(path);
  const InjectedFault fault = next_write_step("write " + path);
  int descriptor = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
  if (descriptor < 0) throw_write_error(path, errno);
  TemporaryFile guard(temporary);
  try {
    write_all(descriptor, fault == InjectedFault::none ? bytes : bytes.substr(0, bytes.size() / 2), path);
    act_on_write_fault(fault, path);
    // On disk before it is renamed into place: after a power loss the name never shows an empty file.
    if (::fsync(descriptor) != 0 && errno != EINVAL) throw_write_error(path, errno);
  } catch (...) {
    ::close(descriptor);
    throw;
  }
  // close() is where some file systems (NFS) report a full disk.
  if (::close(descriptor) != 0) throw_write_error(path, errno);
  rename_atomically(temporary, path);
  guard.release();
}

void write_text_atomically(const std::string& path, const std::string& text) { write_file_atomically(path, text); }

void write_file_atomically_with(const std::string& path, const std::function<void(const std::string& temporary)>& writer) {
  const std::string temporary = temporary_path(path);
  const InjectedFault fault = next_write_step("write " + path);
  TemporaryFile guard(temporary);
  try {
    writer(temporary);
  } catch (const std::exception& error) {
    throw_writer_error(path, error.what());
  }
  std::error_code error;
  uintmax_t size = fs::file_size(temporary, error);
  if (error) throw_writer_error(path, "the writer left no file");
  if (fault != InjectedFault::none) {
    fs::resize_file(temporary, size / 2, error);
    act_on_write_fault(fault, path);
  }
  rename_atomically(temporary, path);
  guard.release();
}

void write_stream_atomically(const std::string& path, const std::function<void(std::ostream& stream)>& writer) {
  write_file_atomically_with(path, [&](const std::string& temporary) {
    std::ofstream stream(temporary, std::ios::binary | std::ios::trunc);
    if (!stream) throw std::runtime_error(os_error_text(errno));
    writer(stream);
    stream.flush();
    if (!stream) throw std::runtime_error(os_error_text(errno));
    stream.close();
    if (!stream) throw std::runtime_error(os_error_text(errno));
  });
}

bool is_partial_file_name(const std::string& name) { return name.find(kPartialMarker) != std::string::npos; }

size_t remove_stale_partial_files(const std::string& folder, bool folder_is_locked) {
  std::error_code error;
  if (!fs::is_directory(folder, error)) return 0;
  const std::string owner_prefix = host_name() + "-";
  size_t removed = 0;
  for (fs::directory_iterator it(folder, error), end; !error && it != end; it.increment(error)) {
    std::string name = it->path().filename().string();
    size_t marker = name.find(kPartialMarker);
    std::error_code type_error;
    if (marker == std::string::npos || !it->is_regular_file(type_error)) continue;
    std::string owner = name.substr(marker + std::string(kPartialMarker).size());
    bool stale = false;
    if (owner.rfind(owner_prefix, 0) == 0) {
      stale = !process_exists(std::atoi(owner.c_str() + owner_prefix.size()));  // atoi stops at the '.'
    } else if (!owner.empty() && owner.find_first_not_of("0123456789") == std::string::npos) {
      stale = !process_exists(std::atoi(owner.c_str()));  // <name>.partial.<pid>: older versions, this host
    } else if (folder_is_locked) {
      // Another host's, or no owner at all (an image writer's <name>.partial.exr): nobody else writes in
      // a folder whose lock the caller holds, so it is a leftover.
      stale = owner.find('-') == std::string::npos;
    }
    std::error_code ignored;
    if (stale && fs::remove(it->path(), ignored)) ++removed;
  }
  return removed;
}

std::string read_text(const std::string& path, const std::string& kind, uintmax_t most_bytes) {
  std::error_code error;
  fs::file_status status = fs::status(path, error);
  if (!fs::exists(status)) throw InputError(fmt::format("{}: file not found", path));
  // Only a regular file: a FIFO would block the read forever, /dev/zero would never end.
  if (!fs::is_regular_file(status)) {
    std::string found = fs::is_directory(status) ? "a folder"
                       : fs::is_fifo(status)    ? "a FIFO (named pipe)"
                       : fs::is_character_file(status) || fs::is_block_file(status) ? "a device"
                                                                                     : "a socket or other special file";
    throw InputError(fmt::format("{}: expected a regular file ({}), found {}", path, kind, found));
  }
  uintmax_t size = fs::file_size(path, error);
  if (!error && size > most_bytes) {
    const bool configuration = most_bytes == kMaximumConfigurationBytes && kind == "a scene or experiment";
    throw InputError(fmt::format("{}: expected {} of at most {:.4g} MiB{}, found {:.1f} MiB", path,
                                 configuration ? "a configuration file" : kind, most_bytes / 1048576.0,
                                 configuration ? " (meshes and maps belong in asset files)" : "", size / 1048576.0));
  }
  std::ifstream stream(path, std::ios::binary);
  if (!stream) throw InputError(fmt::format("{}: cannot open file for reading: {}", path, os_error_text(errno)));
  std::stringstream buffer;
  buffer << stream.rdbuf();
  return buffer.str();
}

void ensure_folder(const std::string& path) {
  std::error_code error;
  if (path.empty()) throw InputError("expected an output folder, found an empty path");
  if (fs::is_symlink(fs::symlink_status(path, error)) && !fs::exists(path, error)) {
    throw InputError(fmt::format("{}: expected an output folder, found a symbolic link to {}, which does not exist", path,
                                 fs::read_symlink(path, error).string()));
  }
  if (std::filesystem::exists(path) && !std::filesystem::is_directory(path)) {
    throw InputError(fmt::format("{}: expected an output folder, found an existing file", path));
  }
  std::filesystem::create_directories(path, error);
  if (error) throw InputError(fmt::format("{}: cannot create the output folder: {}", path, error.message()));
}

}  // namespace causticbench
