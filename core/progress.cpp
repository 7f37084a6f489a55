#include "core/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

#include <fmt/format.h>

namespace causticbench {

namespace {
bool quiet_progress = false;
}

void Progress::set_quiet(bool quiet) { quiet_progress = quiet; }

std::string format_duration(double seconds) {
  if (!(seconds >= 0.0) || seconds > 1e7) return "?";
  if (seconds < 60.0) return fmt::format("{:.1f}s", seconds);
  int total = static_cast<int>(seconds + 0.5);
  if (total < 3600) return fmt::format("{}m{:02d}s", total / 60, total % 60);
  return fmt::format("{}h{:02d}m", total / 3600, (total % 3600) / 60);
}

Progress::Progress(std::string label, double total)
    : label_(std::move(label)),
      total_(total),
      start_(std::chrono::steady_clock::now()),
      last_print_(start_),
      terminal_(isatty(STDERR_FILENO)) {}

Progress::~Progress() {
  if (!finished_ && terminal_ && !quiet_progress) std::fputs("\n", stderr);
}

void Progress::update(double done, const std::string& detail) {
  update_fraction(total_ > 0.0 ? done / total_ : 0.0, detail);
}

void Progress::update_fraction(double fraction, const std::string& detail) {
  if (quiet_progress) return;
  auto now = std::chrono::steady_clock::now();
  double since_print = std::chrono::duration<double>(now - last_print_).count();
  if (since_print < (terminal_ ? 0.2 : 5.0)) return;
  last_print_ = now;
  print(fraction, detail, false);
}

void Progress::finish(const std::string& detail) {
  if (finished_) return;
  finished_ = true;
  if (quiet_progress) return;
  print(1.0, detail, true);
}

void Progress::print(double fraction, const std::string& detail, bool final_line) {
  double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  fraction = std::clamp(fraction, 0.0, 1.0);
  std::string eta = final_line ? "done" : (fraction > 0.0 ? "ETA " + format_duration(elapsed * (1.0 - fraction) / fraction) : "ETA ?");
  std::string line = fmt::format("{}: {:5.1f}% {} elapsed {}{}", label_, fraction * 100.0, eta, format_duration(elapsed),
                                 detail.empty() ? "" : " | " + detail);
  if (terminal_) {
    fmt::print(stderr, "\r\033[2K{}{}", line, final_line ? "\n" : "");
  } else {
    fmt::print(stderr, "{}\n", line);
  }
  std::fflush(stderr);
}

}  // namespace causticbench
