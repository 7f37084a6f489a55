// The method-independent side of `causticbench render --dump-frame DIR`: DIR/method.txt names the
// method whose format holds the rest of the folder, and each method that can dump a frame registers a
// FrameDumpFormat (causticbench_add_gpu_backend, cmake/methods.cmake) that reads the folder's size and receivers and replays the
// frame on a Vulkan device. causticbench-gpubench and `causticbench gpu-compare` know only this header,
// so a new method adds its replay without touching them. Depends only on the C++ standard library
// (and declares gpu::Context), because causticbench-gpubench links nothing but the Vulkan loader.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace causticbench {

namespace gpu {
class Context;
}

// DIR/method.txt: one line, the method's name. Written under a temporary name and renamed.
void write_dump_method(const std::string& folder, const std::string& method);
// The name in DIR/method.txt. Dumps written before method.txt existed were all pinhole's: a folder with
// frame.txt and no method.txt is "pinhole". Throws std::runtime_error naming method.txt otherwise.
std::string read_dump_method(const std::string& folder);

// A dump folder's arrays are little-endian float32 files (the outputs cpu_irradiance.bin and
// vulkan_irradiance.bin hold RGBA per pixel). Written under a temporary name and renamed, so that a
// reader sees the whole file or none of it; errors throw std::runtime_error naming the file.
void write_floats(const std::string& path, const std::vector<float>& values);
std::vector<float> read_floats(const std::string& path);
void write_dump_bytes(const std::string& path, const char* data, size_t bytes);
// Arrays of 32-bit words that are not all floats (indices, packed texels): the same files, the bits
// copied, never converted.
void write_words(const std::string& path, const std::vector<uint32_t>& words);
std::vector<uint32_t> read_words(const std::string& path);
// A frame's scalars: a text file of `name value` lines (written last by each format, so its presence
// marks a complete frame). Throws std::runtime_error naming the file when it is missing or lacks one
// of `required`.
std::map<std::string, double> read_dump_fields(const std::string& path, const std::vector<std::string>& required);

// `text` as a JSON string literal, quotes included (for FrameReplay::facts_json and gpu_timings.json).
std::string json_quoted(const std::string& text);

// What gpubench and gpu-compare need to know of a dumped frame without knowing its method.
struct FrameDumpInfo {
  uint32_t width = 0, height = 0;
  std::vector<uint8_t> receivers;  // 1 per pixel (row-major): 1 where the method computed a caustic
  double evaluations = 0.0;        // the frame's work in the format's evaluation_unit, for a rate
};

// The info of a frame whose receivers are the pixels with receiver_positions' w (RGBA per pixel) non-zero,
// each worth `evaluations_per_receiver` of the format's evaluation_unit.
FrameDumpInfo receiver_dump_info(uint32_t width, uint32_t height, const std::vector<float>& receiver_positions,
                                 double evaluations_per_receiver);

// A dumped frame uploaded to a device, ready to be rendered any number of times.
class FrameReplay {
 public:
  virtual ~FrameReplay();
  // Renders the frame once: RGBA float per pixel, row-major; kernel_ms gets the kernel's device time
  // (timestamp queries, 0 where the queue has none).
  virtual std::vector<float> render(double& kernel_ms) = 0;
  // Method-specific facts for gpu_timings.json: members of a JSON object (`"name": value`), one a line,
  // separated by commas, no braces; empty when there are none.
  virtual std::string facts_json() const;
};

struct FrameDumpFormat {
  std::string method;           // the name in method.txt (the method's registry name)
  std::string evaluation_unit;  // what FrameDumpInfo::evaluations counts, plural ("receiver-sample pairs")
  // gpu-compare's agreement bounds between the dump's cpu_irradiance.bin and vulkan_irradiance.bin:
  // relMSE over the receivers, and |vulkan flux / cpu flux - 1|.
  double relmse_tolerance = 0.0;
  double flux_tolerance = 0.0;
  std::string tolerance_reason;  // why those bounds (printed when the backends disagree)
  // Both throw std::runtime_error naming the file on a missing or malformed dump.
  FrameDumpInfo (*read_info)(const std::string& folder) = nullptr;
  std::unique_ptr<FrameReplay> (*replay)(gpu::Context& context, const std::string& folder) = nullptr;
};

// Every method's format, in the frame_dump_formats.cpp that cmake/methods.cmake generates from the method
// folders' causticbench_add_gpu_backend calls.
const std::vector<FrameDumpFormat>& frame_dump_formats();
// Throws std::runtime_error listing the known formats when `method` has none.
const FrameDumpFormat& frame_dump_format(const std::string& method);

}  // namespace causticbench
