// The trivial baselines of each variant (metrics/baselines.h), scored when the report is written from
// the reference images the runs were measured against: nothing is stored, and a report of an older
// store gets them too.
#include <map>
#include <regex>

#include <fmt/format.h>

#include "core/gbuffer.h"
#include "core/image.h"
#include "reports/report_parts.h"

namespace causticbench::report_detail {

namespace {

// The reference's frames in its folder (frame_NNNN.exr) with their receiver masks (gbuffer_NNNN.exr);
// false when a file is missing or does not fit.
bool read_reference_frames(const fs::path& folder, std::vector<Image>& images, std::vector<std::vector<uint8_t>>& masks) {
  static const std::regex frame_name(R"(frame_(\d{4,})\.exr)");
  std::vector<std::pair<int, fs::path>> frames;
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(folder, error)) {
    std::smatch match;
    const std::string name = entry.path().filename().string();
    if (std::regex_match(name, match, frame_name)) frames.emplace_back(std::stoi(match[1]), entry.path());
  }
  if (error || frames.empty()) return false;
  std::sort(frames.begin(), frames.end());
  try {
    for (const auto& [frame, path] : frames) {
      images.push_back(read_exr(path.string()));
      const Image gbuffer = GBuffer::read_image((folder / (ResultPaths::frame_file(frame, "gbuffer") + ".exr")).string());
      if (gbuffer.channels() <= GBuffer::kReceiverChannel || gbuffer.width() != images.back().width() ||
          gbuffer.height() != images.back().height())
        return false;
      std::vector<uint8_t> mask(gbuffer.pixel_count());
      for (size_t i = 0; i < mask.size(); ++i) mask[i] = gbuffer.at(i, GBuffer::kReceiverChannel) > 0.5f;
      masks.push_back(std::move(mask));
    }
  } catch (const std::exception&) {
    return false;
  }
  return true;
}

}  // namespace

void score_variant_baselines(Report& report) {
  // Variants that share a reference share its baselines: each reference is read and scored once.
  std::map<std::string, std::vector<BaselineScores>> scored;
  for (Variant& variant : report.variants) {
    if (variant.reference_key.empty()) continue;
    auto found = scored.find(variant.reference_key);
    if (found == scored.end()) {
      std::vector<BaselineScores> scores;
      std::vector<Image> images;
      std::vector<std::vector<uint8_t>> masks;
      if (!read_reference_frames(report.reference_folder(variant.reference_key), images, masks)) {
        report.notes.push_back(fmt::format("The reference images of {} cannot be read: no baselines against it.",
                                           variant.reference_key));
      } else {
        try {
          scores = score_baselines(images, masks, report.metrics);
        } catch (const std::exception& problem) {
          report.notes.push_back(
              fmt::format("The baselines of {} could not be scored: {}", variant.reference_key, problem.what()));
        }
      }
      found = scored.emplace(variant.reference_key, std::move(scores)).first;
    }
    variant.baselines = found->second;
  }
}

bool no_better_than_black(const Report& report, const Run& run) {
  const std::optional<double> black = report.variants[run.variant_index].black(report.primary);
  const std::optional<double> value = run.metric(report.primary);
  return black && value && std::isfinite(*value) && !quantity_better(report.primary, *value, *black);
}

std::map<std::string, BlackWins> black_wins(const Report& report) {
  std::map<std::string, BlackWins> wins;
  for (const std::string& metric : report.metrics) {
    // A count of defects, 0 for black and for every sound run alike: a tie there says nothing.
    if (metric == "nonfinite_pixels") continue;
    BlackWins& count = wins[metric];
    for (size_t i : report.ok_runs()) {
      const Run& run = report.runs[i];
      const std::optional<double> black = report.variants[run.variant_index].black(metric);
      const std::optional<double> value = run.metric(metric);
      if (!black || !value || !std::isfinite(*value)) continue;
      ++count.scored;
      if (!quantity_better(metric, *value, *black)) ++count.beaten;
    }
  }
  return wins;
}

}  // namespace causticbench::report_detail
