// Every method's `--dump-frame` format, for causticbench-gpubench and `causticbench gpu-compare`.
// Compiled into causticbench_frame_dumps, which gpubench links: an entry may depend only on gpu/ and
// the standard library.
#include <stdexcept>

#include "methods/frame_dump.h"
#include "methods/lpi/frame_replay.h"
#include "methods/csl/frame_replay.h"
#include "methods/pinhole/frame_replay.h"

namespace causticbench {

const std::vector<FrameDumpFormat>& frame_dump_formats() {
  // One line per method that can dump its frame (MethodInfo::frame_dump); see docs/gpu.md.
  static const std::vector<FrameDumpFormat> formats = {
      pinhole_frame_dump_format(),
      lpi_frame_dump_format(),
      csl_frame_dump_format(),
  };
  return formats;
}

const FrameDumpFormat& frame_dump_format(const std::string& method) {
  std::string known;
  for (const FrameDumpFormat& format : frame_dump_formats()) {
    if (format.method == method) return format;
    known += (known.empty() ? "" : ", ") + format.method;
  }
  throw std::runtime_error("no frame dump format for method '" + method + "' (known formats: " + known +
                           "); add its entry to methods/frame_dumps.cpp");
}

}  // namespace causticbench
