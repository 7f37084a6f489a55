// Shell words for the commands causticbench writes or runs (`slurm`'s jobs, `conform`'s suite, `external`'s program).
#pragma once

#include <string>

namespace causticbench {

// 'text' for the shell, whatever it holds.
inline std::string shell_quoted(const std::string& text) {
  std::string result = "'";
  for (char c : text) result += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return result + "'";
}

}  // namespace causticbench
