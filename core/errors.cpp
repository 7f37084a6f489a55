#include "core/errors.h"

#include <algorithm>
#include <cstdlib>
#include <exception>
#include <typeinfo>

#include <cxxabi.h>

#include <fmt/format.h>

namespace causticbench {

std::string SourceLocation::describe() const {
  if (line <= 0) return file;
  return fmt::format("{}:{}:{}", file, line, column);
}

std::string current_exception_text() {
  try {
    throw;
  } catch (const std::exception& error) {
    return error.what();
  } catch (...) {
    // The thrown object's type, as the C++ runtime names it (an int thrown is "int").
    std::string type = "an unknown type";
    if (const std::type_info* info = abi::__cxa_current_exception_type()) {
      int status = 0;
      char* readable = abi::__cxa_demangle(info->name(), nullptr, nullptr, &status);
      type = status == 0 && readable ? readable : info->name();
      std::free(readable);
    }
    return fmt::format("it threw a value of type {}, which is not a std::exception (throw a std::runtime_error with a "
                       "message instead)",
                       type);
  }
}

void throw_input_error(const SourceLocation& where, std::string_view key, std::string_view expected,
                       std::string_view found) {
  std::string message = where.describe();
  if (!message.empty()) message += ": ";
  if (!key.empty()) message += fmt::format("key '{}': ", key);
  message += fmt::format("expected {}", expected);
  if (!found.empty()) message += fmt::format(", found {}", found);
  throw InputError(message);
}

size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<size_t> previous(b.size() + 1), current(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) previous[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    current[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      size_t substitution = previous[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1);
      current[j] = std::min({previous[j] + 1, current[j - 1] + 1, substitution});
    }
    std::swap(previous, current);
  }
  return previous[b.size()];
}

std::string closest_match(std::string_view word, const std::vector<std::string>& candidates) {
  std::string best;
  size_t best_distance = std::max<size_t>(2, word.size() / 3) + 1;
  for (const std::string& candidate : candidates) {
    size_t distance = edit_distance(word, candidate);
    if (distance < best_distance) {
      best_distance = distance;
      best = candidate;
    }
  }
  if (!best.empty() || word.size() < 2) return best;
  // No near spelling: a name of which the word is a whole part between underscores ("fov" of
  // "fov_degrees", "degrees" too), the shortest such.
  for (const std::string& candidate : candidates) {
    for (size_t at = candidate.find(word); at != std::string::npos; at = candidate.find(word, at + 1)) {
      const bool starts = at == 0 || candidate[at - 1] == '_';
      const bool ends = at + word.size() == candidate.size() || candidate[at + word.size()] == '_';
      if (starts && ends && candidate != word && (best.empty() || candidate.size() < best.size())) best = candidate;
    }
  }
  return best;
}

std::string did_you_mean(std::string_view word, const std::vector<std::string>& candidates) {
  std::string match = closest_match(word, candidates);
  return match.empty() ? std::string() : fmt::format(" (did you mean '{}'?)", match);
}

std::string join(const std::vector<std::string>& words, std::string_view separator) {
  std::string result;
  for (size_t i = 0; i < words.size(); ++i) {
    if (i) result += separator;
    result += words[i];
  }
  return result;
}

}  // namespace causticbench
