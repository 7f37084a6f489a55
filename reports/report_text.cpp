// Reading the stored JSON and writing values as text (declared in report_text.h): the helpers that the
// loading, the tables, the claims and every writer share.
#include "reports/report_text.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>

#include "core/errors.h"
#include "store/result_paths.h"

namespace causticbench::report_detail {

namespace fs = std::filesystem;
using nlohmann::json;

json read_json(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(fmt::format("cannot read {}", path.string()));
  try {
    return json::parse(in);
  } catch (const json::exception& error) {
    throw InputError(fmt::format("{} is not valid JSON: {}", path.string(), error.what()));
  }
}

std::optional<double> number(const json& object, const std::string& key) {
  if (!object.is_object()) return std::nullopt;
  auto it = object.find(key);
  if (it == object.end() || !it->is_number()) return std::nullopt;
  return it->get<double>();
}

const json& member(const json& object, const std::string& key) {
  static const json null_value;
  if (!object.is_object()) return null_value;
  auto it = object.find(key);
  return it == object.end() ? null_value : *it;
}

std::string string_member(const json& object, const std::string& key, const std::string& fallback) {
  const json& value = member(object, key);
  return value.is_string() ? value.get<std::string>() : fallback;
}

bool finite(const std::optional<double>& value) { return value && std::isfinite(*value); }

std::string num(double value) {
  if (std::isnan(value)) return "NaN";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  return fmt::format("{:.4g}", value);
}

std::string bytes_text(double bytes) {
  static const char* const units[] = {"B", "KiB", "MiB", "GiB", "TiB"};
  int unit = 0;
  while (bytes >= 1024.0 && unit < 4) {
    bytes /= 1024.0;
    ++unit;
  }
  return unit == 0 ? fmt::format("{:.0f} B", bytes) : fmt::format("{:.3g} {}", bytes, units[unit]);
}

std::string value_text(const json& value) {
  if (value.is_string()) return value.get<std::string>();
  if (value.is_number_float()) return fmt::format("{:.6g}", value.get<double>());
  if (value.is_null()) return "";
  return value.dump();
}

std::string knobs_text(const json& knobs, const std::string& separator) {
  std::string text;
  if (!knobs.is_object()) return text;
  for (const auto& [name, value] : knobs.items()) {
    if (!text.empty()) text += separator;
    text += name + "=" + value_text(value);
  }
  return text;
}

void flatten(const json& value, const std::string& prefix, std::vector<std::pair<std::string, std::string>>& out) {
  if (value.is_object()) {
    for (const auto& [name, child] : value.items()) flatten(child, prefix.empty() ? name : prefix + "." + name, out);
  } else if (value.is_array() &&
             std::all_of(value.begin(), value.end(), [](const json& v) { return v.is_primitive(); })) {
    std::vector<std::string> parts;
    for (const json& item : value) parts.push_back(value_text(item));
    out.push_back({prefix, join(parts, ", ")});
  } else {
    out.push_back({prefix, value.is_primitive() ? value_text(value) : value.dump()});
  }
}

std::string html_escape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&#39;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string script_json(const nlohmann::json& value) {
  const std::string text = value.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  std::string out;
  out.reserve(text.size());
  for (char c : text) out += c == '<' ? std::string("\\u003c") : std::string(1, c);
  return out;
}

std::string md_text(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string md_escape(const std::string& text) { return md_table_cell(md_text(text)); }

std::string md_table_cell(const std::string& markdown) {
  std::string out;
  for (char c : markdown) {
    if (c == '|')
      out += "\\|";
    else if (c == '\n' || c == '\r')
      out += ' ';
    else
      out += c;
  }
  return out;
}

std::string file_safe(const std::string& text) {
  std::string out;
  for (char c : text) out += std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' ? c : '_';
  return out.empty() ? "run" : out;
}

std::string frame_file(int64_t frame, const std::string& prefix) {
  return ResultPaths::frame_file(static_cast<int>(frame), prefix) + ".exr";
}

}  // namespace causticbench::report_detail
