// Progress with ETA for long work. On a terminal one line is rewritten in place; otherwise (logs, CI)
// a plain line is printed at most every few seconds. Everything goes to stderr.
#pragma once

#include <chrono>
#include <string>

namespace causticbench {

class Progress {
 public:
  // total: units of work (passes, photons, runs); 0 means unknown.
  Progress(std::string label, double total);
  ~Progress();
  // Reports absolute progress `done` with an optional detail (e.g. "reference error 3.2e-3").
  void update(double done, const std::string& detail = "");
  // Work whose end is judged by a measured quantity: fraction in [0, 1] estimates completion.
  void update_fraction(double fraction, const std::string& detail);
  void finish(const std::string& detail = "");
  static void set_quiet(bool quiet);

 private:
  void print(double fraction, const std::string& detail, bool final_line);
  std::string label_;
  double total_;
  std::chrono::steady_clock::time_point start_, last_print_;
  bool terminal_;
  bool finished_ = false;
};

std::string format_duration(double seconds);

}  // namespace causticbench
