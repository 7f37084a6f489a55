#include "methods/external/command_template.h"

#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "core/errors.h"
#include "core/shell.h"

namespace causticbench {

const std::map<std::string, std::string>& command_placeholders() {
  static const std::map<std::string, std::string> placeholders = {
      {"scene", "the frame's scene, a causticbench scene file (scene.json)"},
      {"world", "the frame in world space (world.json)"},
      {"gbuffer", "the G-buffer to compute E_c at (gbuffer.exr)"},
      {"out", "where the program writes E_c (an RGB EXR of the G-buffer's size)"},
      {"stats", "where the program may write its timings and counters (JSON)"},
      {"folder", "the folder of these files"},
      {"frame", "the frame index"},
      {"width", "the G-buffer's width in pixels"},
      {"height", "the G-buffer's height in pixels"},
      {"causticbench", "the causticbench executable that runs the sweep"},
  };
  return placeholders;
}

std::string expand_command(const std::string& command, const std::map<std::string, std::string>& values) {
  std::string result;
  // The shell's quoting as it reads the command: a value is quoted for the shell only where the shell
  // reads it unquoted. Inside '...' or "..." the value's own quotes would end the user's ('$(touch x)' in
  // "{x}" is run by the shell; in sh -c '... {x}' by the inner one), so a placeholder there is refused.
  char quote = 0;  // '\'', '"' or 0
  for (size_t i = 0; i < command.size(); ++i) {
    const char c = command[i];
    if (c == '\\' && quote != '\'' && i + 1 < command.size()) {
      const char next = command[i + 1];
      if (next == '\'' || next == '"' || next == '\\') {  // an escaped quote or backslash: no quoting changes
        result += c;
        result += next;
        ++i;
        continue;
      }
      // \{x} would escape the value's opening quote and leave the value unquoted.
      if (next == '{' && !(i + 2 < command.size() && command[i + 2] == '{'))
        throw std::invalid_argument(fmt::format("a backslash before the placeholder at character {}: it would unquote its "
                                                "value; remove it",
                                                i + 2));
    }
    if ((c == '{' || c == '}') && i + 1 < command.size() && command[i + 1] == c) {
      result += c;
      ++i;
      continue;
    }
    if (c == '}') throw std::invalid_argument(fmt::format("a '}}' at character {} without its '{{' (write '}}}}' for a brace)", i + 1));
    if (c != '{') {
      if ((c == '\'' || c == '"') && (quote == 0 || quote == c)) quote = quote == 0 ? c : 0;
      result += c;
      continue;
    }
    const size_t close = command.find('}', i + 1);
    if (close == std::string::npos)
      throw std::invalid_argument(fmt::format("a '{{' at character {} without its '}}' (write '{{{{' for a brace)", i + 1));
    const std::string name = command.substr(i + 1, close - i - 1);
    auto it = values.find(name);
    if (it == values.end()) throw std::invalid_argument(fmt::format("an unknown placeholder {{{}}}", name));
    if (quote != 0)
      throw std::invalid_argument(fmt::format(
          "the placeholder {{{}}} inside {} quotes at character {}: a value is quoted for the shell where the "
          "placeholder stands, and inside quotes its own quotes would let the shell run it; write {{{}}} outside "
          "quotes (--name={{{}}}, not \"{{{}}}\"), and to hand it to a nested shell pass it as an argument "
          "(sh -c 'my_program \"$1\"' sh {{{}}})",
          name, quote == '\'' ? "single" : "double", i + 1, name, name, name, name));
    result += shell_quoted(it->second);
    i = close;
  }
  if (quote != 0) throw std::invalid_argument(fmt::format("a {} quote that is never closed", quote == '\'' ? "single" : "double"));
  return result;
}

std::map<std::string, std::string> program_knobs(const ParamSet& knobs) {
  std::map<std::string, std::string> program;
  for (const auto& [name, value] : knobs.values())
    if (name.rfind("program.", 0) == 0) program[name] = format_param_value(value);
  return program;
}

std::string command_problem(const std::string& command, const std::map<std::string, std::string>& knobs) {
  if (command.find_first_not_of(" \t\n") == std::string::npos)
    return "set `command`, the program to run for each frame, for example \"python3 my_renderer.py {scene} {gbuffer} {out}\"";
  std::map<std::string, std::string> values = knobs;
  std::vector<std::string> known;
  for (const auto& [name, meaning] : command_placeholders()) {
    values[name] = name;
    known.push_back("{" + name + "}");
  }
  for (const auto& [name, value] : knobs) known.push_back("{" + name + "}");
  // {out} filled in with a word no command holds otherwise, to see that it is a placeholder ({{out}} is not).
  const std::string marker = "\x01out\x01";
  values["out"] = marker;
  std::string expanded;
  try {
    expanded = expand_command(command, values);
  } catch (const std::invalid_argument& error) {
    return fmt::format("`command` has {}; it may use {}", error.what(), join(known, ", "));
  }
  if (expanded.find(marker) == std::string::npos)
    return "`command` must pass {out}, where the program writes its E_c image";
  return "";
}

}  // namespace causticbench
