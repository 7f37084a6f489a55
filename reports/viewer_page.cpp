// viewer.html: the report's image viewer (reports/templates/viewer.html), with the index of its entries
// (reports/viewer_data.h) written into the page, so that it opens from disk with no server.
#include <string>

#include "reports/report_parts.h"
#include "templates/viewer.html.h"

namespace causticbench::report_detail {

std::string viewer_document(const Report& report) {
  json index = report.viewer;
  index["experiment"] = report.name;
  // Escaped as the report's own plots are: "<!--" in a label would otherwise blank the page.
  const std::string text = script_json(index);
  std::string page = kViewerPage;
  const std::string placeholder = "\"__CAUSTICBENCH_VIEWER_INDEX__\"";
  const size_t at = page.find(placeholder);
  if (at == std::string::npos) throw std::logic_error("reports/templates/viewer.html has no index placeholder");
  page.replace(at, placeholder.size(), text);
  return page;
}

}  // namespace causticbench::report_detail
