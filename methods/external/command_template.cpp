#include "methods/external/command_template.h"

#include <cctype>
#include <set>
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

std::string placeholder_variable(const std::string& name) {
  std::string variable = "CAUSTICBENCH_";
  for (char c : name) variable += std::isalnum(static_cast<unsigned char>(c)) ? static_cast<char>(std::toupper(c)) : '_';
  return variable;
}

std::string expand_command(const std::string& command, const std::map<std::string, std::string>& values) {
  // No value is ever pasted into the command's text. Each placeholder becomes a reference to a shell
  // variable, and the variables are assigned, single-quoted, in lines of their own before the command:
  // the shell never parses the result of an expansion again, so a value such as $(touch x), `touch x` or
  // '; touch x; ' reaches the program as text wherever its placeholder stands (in "$(dirname {out})", a
  // here-document or arithmetic alike). Where the placeholder stands outside quotes the reference is
  // double-quoted, so that the value stays one word; inside the command's double quotes it is bare.
  // Inside single quotes no expansion happens at all, so a placeholder there would reach the program
  // as the variable's name: refused, with the fix. So is one after '$' or a backslash, which would
  // change what the reference means. The quotes are followed as sh reads them at the top level; where
  // this reading is wrong (quotes nested in $(...)), the worst outcome is a value split into words,
  // never a value run.
  std::string body, preamble;
  std::set<std::string> assigned;
  char quote = 0;  // '\'', '"' or 0
  for (size_t i = 0; i < command.size(); ++i) {
    const char c = command[i];
    if (c == '\\' && quote != '\'' && i + 1 < command.size()) {
      const char next = command[i + 1];
      if (next == '{' && !(i + 2 < command.size() && command[i + 2] == '{'))
        throw std::invalid_argument(fmt::format("a backslash before the placeholder at character {}; remove it", i + 2));
      body += c;
      body += next;  // an escaped character: a quote or backslash so escaped changes no quoting
      ++i;
      continue;
    }
    if ((c == '{' || c == '}') && i + 1 < command.size() && command[i + 1] == c) {
      body += c;
      ++i;
      continue;
    }
    if (c == '}') throw std::invalid_argument(fmt::format("a '}}' at character {} without its '{{' (write '}}}}' for a brace)", i + 1));
    if (c != '{') {
      if ((c == '\'' || c == '"') && (quote == 0 || quote == c)) quote = quote == 0 ? c : 0;
      body += c;
      continue;
    }
    const size_t close = command.find('}', i + 1);
    if (close == std::string::npos)
      throw std::invalid_argument(fmt::format("a '{{' at character {} without its '}}' (write '{{{{' for a brace)", i + 1));
    const std::string name = command.substr(i + 1, close - i - 1);
    auto it = values.find(name);
    if (it == values.end()) throw std::invalid_argument(fmt::format("an unknown placeholder {{{}}}", name));
    if (quote == '\'')
      throw std::invalid_argument(fmt::format(
          "the placeholder {{{}}} inside single quotes at character {}: the shell expands nothing there; write it "
          "outside them, and to hand a value to a nested shell pass it as an argument (sh -c 'my_program \"$1\"' sh "
          "{{{}}})",
          name, i + 1, name));
    if (!body.empty() && body.back() == '$')
      throw std::invalid_argument(fmt::format("a '$' before the placeholder {{{}}} at character {}; remove it", name, i + 1));
    const std::string variable = placeholder_variable(name);
    if (assigned.insert(variable).second) preamble += "export " + variable + "=" + shell_quoted(it->second) + "\n";
    body += quote == '"' ? "${" + variable + "}" : "\"${" + variable + "}\"";
    i = close;
  }
  if (quote != 0) throw std::invalid_argument(fmt::format("a {} quote that is never closed", quote == '\'' ? "single" : "double"));
  return preamble + body;
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
