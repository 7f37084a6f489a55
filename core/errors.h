// Errors in user input (scene, experiment, asset, command line) and the helpers that make them clear.
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace causticbench {

// Where a piece of input came from: a file with 1-based line and column, or a description such as
// "--set" for command-line values. Line 0 means "no position known".
struct SourceLocation {
  std::string file;
  int line = 0;
  int column = 0;

  std::string describe() const;
};

// Thrown for every defect in user input. The command line turns it into exit code 2 before any work
// starts; the message already names the file, line, column, key, what was expected and what was found.
class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& message) : std::runtime_error(message) {}
};

// A program a run hands its work to (the external method's) failed: neither a defect of the input, found
// before any work, nor a bug of causticbench. `render` says so and exits with 1; a sweep records the run
// as failed with the message.
class ProgramError : public std::runtime_error {
 public:
  explicit ProgramError(const std::string& message) : std::runtime_error(message) {}
};

// A method's own code broke the interface's promises (render() returned an image of another size than
// the G-buffer's, or threw something that is not a std::exception): that run fails with this message,
// the sweep goes on; `render` exits with 1.
class MethodError : public std::runtime_error {
 public:
  explicit MethodError(const std::string& message) : std::runtime_error(message) {}
};

// Inside a catch block: the message of the exception being handled, what() of a std::exception, or a
// sentence naming what else was thrown (a plugin's `throw 42;`), so that a catch (...) can report it.
std::string current_exception_text();

[[noreturn]] void throw_input_error(const SourceLocation& where, std::string_view key, std::string_view expected,
                                    std::string_view found);

// Levenshtein distance, for "did you mean" suggestions.
size_t edit_distance(std::string_view a, std::string_view b);

// The closest candidate within a small edit distance, or "" when none is close enough.
std::string closest_match(std::string_view word, const std::vector<std::string>& candidates);

// " (did you mean 'x'?)" or "" when nothing is close.
std::string did_you_mean(std::string_view word, const std::vector<std::string>& candidates);

std::string join(const std::vector<std::string>& words, std::string_view separator);

}  // namespace causticbench
