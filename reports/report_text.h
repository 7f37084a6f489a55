// The small helpers every part of the report uses: reading members of the stored JSON without
// throwing, and writing numbers, knobs and sizes as a person reads them, escaped for HTML or Markdown.
// Internal to reports/ (see report_model.h); the public interface is reports/report.h.
#pragma once

#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace causticbench::report_detail {

// The file as JSON; InputError when it cannot be read or parsed.
nlohmann::json read_json(const std::filesystem::path& path);

// A member of a JSON object, without throwing: a number (none when absent or not a number), any value
// (null when absent or `object` is no object), a string (`fallback` otherwise).
std::optional<double> number(const nlohmann::json& object, const std::string& key);
const nlohmann::json& member(const nlohmann::json& object, const std::string& key);
std::string string_member(const nlohmann::json& object, const std::string& key, const std::string& fallback = "");

bool finite(const std::optional<double>& value);

// Four significant digits: enough to compare, short enough to read in a table.
std::string num(double value);
// "512 B", "1.5 MiB".
std::string bytes_text(double bytes);
// A knob or paper value as a person writes it.
std::string value_text(const nlohmann::json& value);
// "name=value, name=value" of a JSON object's members.
std::string knobs_text(const nlohmann::json& knobs, const std::string& separator = ", ");
// environment.json flattened to "key: value" lines, nested objects with dotted keys.
void flatten(const nlohmann::json& value, const std::string& prefix,
             std::vector<std::pair<std::string, std::string>>& out);

std::string html_escape(const std::string& text);
// JSON placed inside a <script> element: no "</script>", "<!--" or "<script" may appear in it, so every
// '<' (JSON has it only inside strings) is written \u003c, which means the same character. Bytes that are
// not UTF-8 become U+FFFD.
std::string script_json(const nlohmann::json& value);
// Text a user supplied (a label, a knob value, a claim, a description, an error) in Markdown: '&', '<' and
// '>' as HTML entities, so that a renderer that keeps HTML shows `<img onerror=...>` instead of running it.
std::string md_text(const std::string& text);
// A Markdown table cell of Markdown text: '|' escaped and line breaks as spaces.
std::string md_table_cell(const std::string& markdown);
// A Markdown table cell of a user's text: md_text, then md_table_cell.
std::string md_escape(const std::string& text);
// Letters, digits, '-' and '_' kept, anything else '_': a file name ("run" when empty).
std::string file_safe(const std::string& text);
// "frame_0000.exr" (or with another prefix: "gbuffer_0000.exr").
std::string frame_file(int64_t frame, const std::string& prefix = "frame");

}  // namespace causticbench::report_detail
