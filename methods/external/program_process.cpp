#include "methods/external/program_process.h"

#include <fcntl.h>
#include <signal.h>
#include <poll.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
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

// The largest VmHWM of `pid`'s descendants, without its own: the supervisor is a fork of causticbench,
// whose resident size is causticbench's.
double descendants_peak_bytes(pid_t pid) {
  double peak = 0.0;
  std::ifstream children("/proc/" + std::to_string(pid) + "/task/" + std::to_string(pid) + "/children");
  for (pid_t child = 0; children >> child;) peak = std::max(peak, tree_peak_bytes(child, 1));
  return peak;
}

}  // namespace

namespace {

// Waits up to `milliseconds` for the child to exit, without reaping it (a zombie keeps its process group
// alive, so that killing the group afterwards cannot reach a reused one). A pidfd wakes the moment it
// exits; without one (kernels before 5.3) it sleeps.
bool exited_within(pid_t pid, int pidfd, int milliseconds) {
  siginfo_t info{};
  if (pidfd >= 0) {
    pollfd wait{pidfd, POLLIN, 0};
    poll(&wait, 1, milliseconds);
  } else {
    std::this_thread::sleep_for(std::chrono::milliseconds(milliseconds));
  }
  while (waitid(P_PID, static_cast<id_t>(pid), &info, WEXITED | WNOHANG | WNOWAIT) < 0) {
    if (errno != EINTR) throw std::runtime_error(fmt::format("cannot wait for the program: {}", os_error_text(errno)));
  }
  return info.si_pid == pid;
}

}  // namespace

ProgramExit run_program(const std::string& command, const std::string& stdout_path, const std::string& stderr_path,
                        double timeout_seconds) {
  // Everything the child needs is made before fork: between fork and exec a child of a process with
  // worker threads may only make system calls.
  std::vector<char*> arguments = {const_cast<char*>("sh"), const_cast<char*>("-c"), const_cast<char*>(command.c_str()), nullptr};
  const pid_t parent = getpid();
  // Closed by the exec: the parent reads until then, so that it never samples the child's memory before
  // the exec (a forked child's peak is causticbench's), and learns why the exec failed if it did.
  int started[2];
  if (pipe2(started, O_CLOEXEC) != 0) throw std::runtime_error(fmt::format("cannot start /bin/sh: {}", os_error_text(errno)));
  const auto start = std::chrono::steady_clock::now();
  const pid_t pid = fork();
  if (pid < 0) {
    const int error = errno;
    close(started[0]);
    close(started[1]);
    throw std::runtime_error(fmt::format("cannot start /bin/sh: {}", os_error_text(error)));
  }
  if (pid == 0) {
    // The supervisor: the leader of a process group of its own, in which it starts the shell. When
    // causticbench ends, however it ends (Ctrl-C, SIGTERM from scancel, SIGKILL, an exit), the kernel sends
    // the supervisor SIGHUP (PR_SET_PDEATHSIG), and its handler kills the whole group, the program and
    // everything it forked with it. (The death signal reaches only the process that asked for it: given to
    // the shell, Debian's sh forks even a simple command, and the program would live on.) It is a fork of
    // causticbench that never execs, so between fork and exit it makes only async-signal-safe calls.
    close(started[0]);
    setpgid(0, 0);
    struct sigaction on_parent_death {};
    on_parent_death.sa_handler = [](int) { kill(0, SIGKILL); };
    sigemptyset(&on_parent_death.sa_mask);
    sigaction(SIGHUP, &on_parent_death, nullptr);
    prctl(PR_SET_PDEATHSIG, SIGHUP);
    if (getppid() != parent) kill(0, SIGKILL);  // causticbench died before the line above
    const pid_t shell = fork();
    if (shell < 0) {
      const int error = errno;
      (void)!write(started[1], &error, sizeof error);
      _exit(126);
    }
    if (shell == 0) {
      signal(SIGHUP, SIG_DFL);
      signal(SIGPIPE, SIG_DFL);
      const int files[3] = {open("/dev/null", O_RDONLY), open(stdout_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644),
                            open(stderr_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644)};
      for (int target = 0; target < 3; ++target) {
        if (files[target] < 0 || dup2(files[target], target) < 0) {
          const int error = errno;
          (void)!write(started[1], &error, sizeof error);
          _exit(126);
        }
      }
      for (int file : files)
        if (file > 2) close(file);
      execve("/bin/sh", arguments.data(), environ);
      const int error = errno;
      (void)!write(started[1], &error, sizeof error);
      _exit(127);
    }
    close(started[1]);  // the shell's copy closes at its exec: then causticbench reads the end of the pipe
    // Passing on the shell's signal below must not dump a core of causticbench's whole address space.
    const struct rlimit no_core {0, 0};
    setrlimit(RLIMIT_CORE, &no_core);
    int status = 0;
    while (waitpid(shell, &status, 0) < 0) {
      if (errno != EINTR) _exit(126);
    }
    if (WIFEXITED(status)) _exit(WEXITSTATUS(status));
    // Ended by a signal: the supervisor ends by the same one, so that causticbench reads it as the shell's.
    signal(WTERMSIG(status), SIG_DFL);
    kill(getpid(), WTERMSIG(status));
    _exit(128 + WTERMSIG(status));
  }
  setpgid(pid, pid);  // also here, so that the group exists whichever of the two runs first
  close(started[1]);
  int child_error = 0;
  ssize_t got = 0;
  while ((got = read(started[0], &child_error, sizeof child_error)) < 0 && errno == EINTR) {
  }
  close(started[0]);
  if (got > 0) {
    int ignored = 0;
    waitpid(pid, &ignored, 0);
    throw std::runtime_error(fmt::format("cannot start /bin/sh for the program: {}", os_error_text(child_error)));
  }

  ProgramExit exit;
  const int pidfd = static_cast<int>(syscall(SYS_pidfd_open, pid, 0));
  const auto deadline = start + std::chrono::duration<double>(timeout_seconds);
  try {
    // Sampled every 10 ms at most; the pidfd ends the wait the moment the program exits, so that its
    // time is not rounded up to the next sample.
    for (int wait = 1;; wait = std::min(wait * 2, 10)) {
      exit.peak_bytes = std::max(exit.peak_bytes, descendants_peak_bytes(pid));
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now()).count();
      if (exited_within(pid, pidfd, static_cast<int>(std::clamp<long long>(left, 0, wait)))) break;
      if (std::chrono::steady_clock::now() >= deadline) {
        exit.timed_out = true;
        break;
      }
    }
  } catch (...) {
    kill(-pid, SIGKILL);
    int ignored = 0;
    waitpid(pid, &ignored, 0);
    if (pidfd >= 0) close(pidfd);
    throw;
  }
  exit.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  // The shell is a zombie now (or still running, past its timeout): its group is still its own. Kill
  // what is left in it, then reap the shell.
  kill(-pid, SIGKILL);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (pidfd >= 0) close(pidfd);
  if (!exit.timed_out) {
    if (WIFEXITED(status)) exit.exit_status = WEXITSTATUS(status);
    else if (WIFSIGNALED(status)) exit.signal = WTERMSIG(status);
  }
  return exit;
}

namespace {

// `text` for a terminal and a record: a carriage return (progress bars redraw with them) becomes a line
// break and another control character but a tab '?'. Bytes that are not UTF-8 are left to the store,
// which writes every record with U+FFFD in their place (store/run_folders.cpp).
std::string printable(std::string text) {
  for (char& c : text) {
    if (c == '\r') c = '\n';
    else if (static_cast<unsigned char>(c) < 0x20 && c != '\n' && c != '\t') c = '?';
  }
  return text;
}

}  // namespace

std::string file_tail(const std::string& path, int lines) {
  std::ifstream file(path, std::ios::binary);
  if (!file) return "";
  file.seekg(0, std::ios::end);
  const std::streamoff size = file.tellg();
  const std::streamoff keep = std::min<std::streamoff>(size, 4096);
  file.seekg(size - keep);
  std::string text(static_cast<size_t>(keep), '\0');
  file.read(text.data(), keep);
  text = printable(text);
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
