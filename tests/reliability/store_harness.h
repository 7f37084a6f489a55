// What tests/test_reliability_store.cpp and test_reliability_references.cpp drive and inspect the results
// store with: `causticbench` processes started with their own environment (CAUSTICBENCH_FAULT_INJECT) and
// output file, run two at a time, and the reader's view of a results folder: what a reader would find
// half written, and what a killed process left that the next run must clean up.
#pragma once

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <optional>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "store/record_check.h"
#include "store/result_paths.h"
#include "store/run_folders.h"
#include "store/store_files.h"
#include "store/store_lock.h"
#include "store/build_cache.h"

namespace causticbench::store_harness {

namespace fs = std::filesystem;

inline std::string read_all(const fs::path& path) {
  std::ifstream stream(path, std::ios::binary);
  std::stringstream text;
  text << stream.rdbuf();
  return text.str();
}

inline size_t count_of(const std::string& text, const std::string& part) {
  size_t count = 0;
  for (size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++count;
  return count;
}

// A `causticbench` process: its arguments, extra environment entries ("NAME=value") and an output file
// that gets its stdout and stderr.
class Process {
 public:
  Process(const std::vector<std::string>& arguments, const std::string& output, const std::vector<std::string>& environment = {})
      : output_(output) {
    // Everything the child needs is built before fork(): after it, the child only redirects and execs.
    std::vector<std::string> argv_text = {CAUSTICBENCH_BINARY, "-q"};
    argv_text.insert(argv_text.end(), arguments.begin(), arguments.end());
    std::vector<std::string> env_text = environment;
    for (char** entry = environ; *entry; ++entry) {
      if (std::string(*entry).rfind("CAUSTICBENCH_FAULT_INJECT=", 0) != 0) env_text.push_back(*entry);
    }
    std::vector<char*> argv, envp;
    for (std::string& text : argv_text) argv.push_back(text.data());
    for (std::string& text : env_text) envp.push_back(text.data());
    argv.push_back(nullptr);
    envp.push_back(nullptr);
    int file = ::open(output.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    pid_ = fork();
    if (pid_ == 0) {
      dup2(file, 1);
      dup2(file, 2);
      execve(argv[0], argv.data(), envp.data());
      _exit(127);
    }
    ::close(file);
  }

  // Waits for the process; returns its exit code, or 128 + the signal that ended it.
  int wait() {
    if (!ended_ && pid_ > 0) waitpid(pid_, &status_, 0);
    ended_ = true;
    return WIFEXITED(status_) ? WEXITSTATUS(status_) : 128 + WTERMSIG(status_);
  }
  // Sends `signal` (SIGKILL: as a scheduler ends a job past its time) unless it ended.
  void kill_with(int signal) {
    if (running()) ::kill(pid_, signal);
  }
  bool running() const {
    if (!ended_ && pid_ > 0 && waitpid(pid_, &status_, WNOHANG) == pid_) ended_ = true;
    return !ended_;
  }
  std::string output() const { return read_all(output_); }

  // Waits until the output holds `text` (or the process ends, or `seconds` pass).
  bool wait_for_output(const std::string& text, double seconds = 30.0) const {
    auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < deadline) {
      if (output().find(text) != std::string::npos) return true;
      if (!running()) return output().find(text) != std::string::npos;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return false;
  }

 private:
  std::string output_;
  pid_t pid_ = -1;
  mutable int status_ = 0;
  mutable bool ended_ = false;
};

struct Finished {
  int code = 0;
  std::string output;
};

inline Finished run_process(const std::vector<std::string>& arguments, const std::string& output,
                            const std::vector<std::string>& environment = {}) {
  Process process(arguments, output, environment);
  int code = process.wait();
  return {code, process.output()};
}

// Runs cases(0 .. count-1) on two threads: the cases are processes, and the machine has two cores.
inline void for_each_in_parallel(size_t count, const std::function<void(size_t)>& run_case) {
  std::atomic<size_t> next{0};
  auto worker = [&] {
    for (size_t index = next++; index < count; index = next++) run_case(index);
  };
  std::thread other(worker);
  worker();
  other.join();
}

// The numbered write steps that `trace` printed: step number -> description.
inline std::vector<std::pair<int, std::string>> traced_steps(const std::string& output) {
  static const std::regex line("fault injection: step ([0-9]+): (write|rename|commit|replace|discard) (.*)");
  std::vector<std::pair<int, std::string>> steps;
  std::stringstream lines(output);
  for (std::string text; std::getline(lines, text);) {
    std::smatch match;
    if (std::regex_match(text, match, line)) steps.push_back({std::stoi(match[1].str()), match[2].str() + " " + match[3].str()});
  }
  return steps;
}

// Holds a store lock, as another live `causticbench` process would.
class HeldLock {
 public:
  explicit HeldLock(const std::string& path) : lock_(StoreLock::try_acquire(path)) {}
  void release() { lock_.reset(); }

 private:
  std::optional<StoreLock> lock_;
};

inline bool is_invisible(const std::string& name) {
  return name.rfind(".partial-", 0) == 0 || name.find(".partial.") != std::string::npos || name == ".locks";
}

// What a reader of `results` would find half written: a JSON file that does not parse, a run folder whose
// record fails the store's checks, a reference frame or a build whose files do not match their record.
// Staging folders, temporary files and locks are not looked at: no reader ever opens them.
inline std::vector<std::string> half_written(const fs::path& results) {
  std::vector<std::string> problems;
  if (!fs::exists(results)) return problems;
  for (auto it = fs::recursive_directory_iterator(results); it != fs::recursive_directory_iterator(); ++it) {
    const fs::path path = it->path();
    const std::string name = path.filename().string();
    if (is_invisible(name)) {
      if (it->is_directory()) it.disable_recursion_pending();
      continue;
    }
    const std::string parent = path.parent_path().filename().string();
    if (it->is_directory() && parent == "runs") {
      StoredRun stored = inspect_stored_run(path.string());
      if (stored.state != StoredRun::State::stored) problems.push_back(path.string() + ": " + stored.problem);
    } else if (it->is_directory() && parent == "builds") {
      nlohmann::json record = nlohmann::json::parse(read_all(path / "build.json"), nullptr, false);
      if (!record.is_object() || record["files"] != build_file_checksums(path.string()))
        problems.push_back(path.string() + ": build.json missing or its files differ");
    } else if (it->is_regular_file() && path.extension() == ".json") {
      nlohmann::json record = nlohmann::json::parse(read_all(path), nullptr, false);
      if (!record.is_object()) problems.push_back(path.string() + ": not a JSON object");
      if (name.rfind("record_", 0) == 0 && record.is_object()) {
        for (const char* image : {"image", "gbuffer"}) {
          if (!record.contains(image) || !record[image].contains("file")) {
            problems.push_back(path.string() + ": no checksum of its " + image);
            continue;
          }
          std::optional<std::string> bytes = read_file_bytes((path.parent_path() / record[image]["file"].get<std::string>()).string());
          std::string problem = bytes ? checksum_problem(record[image], *bytes) : "missing";
          if (!problem.empty()) problems.push_back(path.string() + ": its " + image + ": " + problem);
        }
      }
    }
  }
  return problems;
}

// What killed processes left that a finished run must have cleaned up: staging folders and temporary files.
inline std::vector<std::string> leftovers(const fs::path& results) {
  std::vector<std::string> found;
  if (!fs::exists(results)) return found;
  for (auto it = fs::recursive_directory_iterator(results); it != fs::recursive_directory_iterator(); ++it) {
    std::string name = it->path().filename().string();
    if (name == ".locks") it.disable_recursion_pending();
    else if (is_invisible(name)) found.push_back(it->path().string());
  }
  return found;
}

}  // namespace causticbench::store_harness
