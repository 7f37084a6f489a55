#include "methods/external/program_process.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <fstream>
#include <thread>
#include <vector>

#include <fmt/format.h>

#include "core/files.h"

extern char** environ;

namespace causticbench {

std::string ProgramExit::describe(double timeout_seconds) const {
  if (timed_out) return fmt::format("ran past its timeout of {:g} s and was killed", timeout_seconds);
  if (signal != 0) return fmt::format("was killed by signal {} ({})", signal, strsignal(signal));
  return fmt::format("exited with status {}", exit_status);
}

namespace {

// The largest VmHWM (the peak resident size of a process's own memory since its exec) of `pid` and its
// descendants, found through /proc/<pid>/task/<pid>/children; 0 for what is gone. Not wait4's ru_maxrss:
// a process started by posix_spawn (or fork) inherits the peak of the sweep's own memory at its exec, so
// that figure is causticbench's size, not the program's.
double tree_peak_bytes(pid_t pid, int depth = 0) {
  double peak = 0.0;
  std::ifstream status("/proc/" + std::to_string(pid) + "/status");
  for (std::string line; std::getline(status, line);) {
    if (line.rfind("VmHWM:", 0) == 0) {
      peak = std::stod(line.substr(6)) * 1024.0;  // "VmHWM:    1234 kB"
      break;
    }
  }
  if (depth > 16) return peak;
  std::ifstream children("/proc/" + std::to_string(pid) + "/task/" + std::to_string(pid) + "/children");
  for (pid_t child = 0; children >> child;) peak = std::max(peak, tree_peak_bytes(child, depth + 1));
  return peak;
}

}  // namespace

ProgramExit run_program(const std::string& command, const std::string& stdout_path, const std::string& stderr_path,
                        double timeout_seconds) {
  // Everything the child needs is made before fork: between fork and exec a child of a process with
  // worker threads may only make system calls.
  std::vector<char*> arguments = {const_cast<char*>("sh"), const_cast<char*>("-c"), const_cast<char*>(command.c_str()), nullptr};
  const pid_t parent = getpid();
  const auto start = std::chrono::steady_clock::now();
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error(fmt::format("cannot start /bin/sh: {}", os_error_text(errno)));
  if (pid == 0) {
    // A group of its own, so that the timeout kills the shell and everything it started; and killed with
    // causticbench (PR_SET_PDEATHSIG), so that a sweep stopped by Ctrl-C or a kill leaves no program
    // running on (the shell, or the program it execs; what a compound command forks lives on).
    setpgid(0, 0);
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (getppid() != parent) _exit(127);  // causticbench died before the line above
    signal(SIGPIPE, SIG_DFL);
    const int input = open("/dev/null", O_RDONLY);
    const int output = open(stdout_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int errors = open(stderr_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (input < 0 || output < 0 || errors < 0) _exit(126);
    dup2(input, 0);
    dup2(output, 1);
    dup2(errors, 2);
    execve("/bin/sh", arguments.data(), environ);
    _exit(127);
  }
  setpgid(pid, pid);  // also here, so that the group exists whichever of the two runs first

  ProgramExit exit;
  int status = 0;
  const auto deadline = start + std::chrono::duration<double>(timeout_seconds);
  auto pause = std::chrono::microseconds(200);
  for (;;) {
    const pid_t done = waitpid(pid, &status, WNOHANG);
    if (done == pid) break;
    if (done < 0 && errno != EINTR) throw std::runtime_error(fmt::format("cannot wait for the program: {}", os_error_text(errno)));
    if (std::chrono::steady_clock::now() >= deadline) {
      kill(-pid, SIGKILL);
      while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
      }
      exit.timed_out = true;
      break;
    }
    exit.peak_bytes = std::max(exit.peak_bytes, tree_peak_bytes(pid));
    // Polled, in steps growing to 10 ms: a frame's program that takes a millisecond is not charged 10.
    std::this_thread::sleep_for(pause);
    pause = std::min(pause * 2, std::chrono::microseconds(10000));
  }
  exit.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  kill(-pid, SIGKILL);  // whatever it left running in its group
  if (!exit.timed_out) {
    if (WIFEXITED(status)) exit.exit_status = WEXITSTATUS(status);
    else if (WIFSIGNALED(status)) exit.signal = WTERMSIG(status);
  }
  return exit;
}

std::string file_tail(const std::string& path, int lines) {
  std::ifstream file(path, std::ios::binary);
  if (!file) return "";
  file.seekg(0, std::ios::end);
  const std::streamoff size = file.tellg();
  const std::streamoff keep = std::min<std::streamoff>(size, 4096);
  file.seekg(size - keep);
  std::string text(static_cast<size_t>(keep), '\0');
  file.read(text.data(), keep);
  while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
  if (text.empty()) return "";
  size_t begin = text.size();
  for (int line = 0; line < lines && begin != std::string::npos && begin > 0; ++line) begin = text.rfind('\n', begin - 1);
  if (begin == std::string::npos) begin = 0;
  else if (text[begin] == '\n') ++begin;
  std::string result;
  for (size_t position = begin; position < text.size();) {
    size_t end = text.find('\n', position);
    if (end == std::string::npos) end = text.size();
    result += "  " + text.substr(position, end - position) + "\n";
    position = end + 1;
  }
  return result;
}

}  // namespace causticbench
