// viewer.html: the report's image viewer (reports/templates/viewer.html), with the index of its entries
// (reports/viewer_data.h) written into the page, so that it opens from disk with no server.
#include <string>

#include "reports/report_parts.h"
#include "templates/viewer.html.h"

namespace causticbench::report_detail {

std::string viewer_document(const Report& report) {
  json index = report.viewer;
  index["experiment"] = report.name;
  // In a <script> element "</" would end it early: JSON allows "<\/" for it.
  std::string text = index.dump();
  for (size_t at = text.find("</"); at != std::string::npos; at = text.find("</", at + 3)) text.replace(at, 2, "<\\/");
  std::string page = kViewerPage;
  const std::string placeholder = "\"__CAUSTICBENCH_VIEWER_INDEX__\"";
  const size_t at = page.find(placeholder);
  if (at == std::string::npos) throw std::logic_error("reports/templates/viewer.html has no index placeholder");
  page.replace(at, placeholder.size(), text);
  return page;
}

}  // namespace causticbench::report_detail
