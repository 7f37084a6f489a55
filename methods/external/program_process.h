// Runs external's program: `/bin/sh -c COMMAND` in a process group of its own, its standard output and
// error to files, its standard input from /dev/null, killed with its whole group (SIGKILL) when it runs
// past the timeout. What it leaves running when it exits is killed too, so that no frame's program
// outlives its frame; and the group's leader is a supervisor (a fork of causticbench that waits for the
// shell) that the kernel signals when causticbench ends however it ends (PR_SET_PDEATHSIG) and that then
// kills the group, so that a stopped sweep leaves no program behind.
#pragma once

#include <string>

namespace causticbench {

struct ProgramExit {
  bool timed_out = false;
  int exit_status = -1;  // the status it exited with, or -1 when a signal ended it
  int signal = 0;        // the signal that ended it, or 0
  double seconds = 0.0;  // from start to exit (or to the kill)
  // The largest peak resident size of the program's processes (the shell and its descendants), as
  // sampled while it runs (every 10 ms at most): a lower bound that misses processes shorter than that.
  double peak_bytes = 0.0;
  bool succeeded() const { return !timed_out && exit_status == 0; }
  // "exited with status 1", "was killed by signal 9 (Killed)", "ran past its timeout of 2 s and was killed"
  std::string describe(double timeout_seconds) const;
};

// Runs `command` with `/bin/sh -c`, in the current folder, writing its output to `stdout_path` and
// `stderr_path`. Throws std::runtime_error when the process cannot be started.
ProgramExit run_program(const std::string& command, const std::string& stdout_path, const std::string& stderr_path,
                        double timeout_seconds);

// The last `lines` lines of the file (at most its last 4 KiB), each prefixed with two spaces; "" when it
// is empty or unreadable.
std::string file_tail(const std::string& path, int lines = 20);

}  // namespace causticbench
