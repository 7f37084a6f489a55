#include "methods/lpi/frame_data.h"

#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

namespace causticbench {

void write_lpi_frame_data(const LpiFrameData& frame, const std::string& folder) {
  write_floats(folder + "/receiver_positions.bin", frame.receiver_positions);
  write_floats(folder + "/receiver_normals.bin", frame.receiver_normals);
  write_words(folder + "/objects.bin", frame.objects);
  write_floats(folder + "/lights.bin", frame.lights);
  write_words(folder + "/values.bin", frame.values);
  write_floats(folder + "/scales.bin", frame.scales);
  write_words(folder + "/shells.bin", frame.shells);
  std::ostringstream text;
  text << "width " << frame.width << "\nheight " << frame.height << "\nstorage " << frame.storage << "\nchannels "
       << frame.channels << "\nprecision " << frame.precision << "\noutside " << frame.outside << "\n";
  // Last: its presence marks a complete frame.
  write_dump_bytes(folder + "/frame.txt", text.str().data(), text.str().size());
}

LpiFrameData read_lpi_frame_data(const std::string& folder) {
  LpiFrameData frame;
  std::map<std::string, double> values =
      read_dump_fields(folder + "/frame.txt", {"width", "height", "storage", "channels", "precision", "outside"});
  frame.width = static_cast<uint32_t>(values["width"]);
  frame.height = static_cast<uint32_t>(values["height"]);
  frame.storage = static_cast<uint32_t>(values["storage"]);
  frame.channels = static_cast<uint32_t>(values["channels"]);
  frame.precision = static_cast<uint32_t>(values["precision"]);
  frame.outside = static_cast<uint32_t>(values["outside"]);
  if (frame.storage > 1 || (frame.channels != 3 && frame.channels != 9) || frame.precision > 3 || frame.outside > 2) {
    throw std::runtime_error(folder + "/frame.txt: storage must be 0 or 1, channels 3 or 9, precision 0 .. 3, outside 0 .. 2");
  }
  frame.receiver_positions = read_floats(folder + "/receiver_positions.bin");
  frame.receiver_normals = read_floats(folder + "/receiver_normals.bin");
  frame.objects = read_words(folder + "/objects.bin");
  frame.lights = read_floats(folder + "/lights.bin");
  frame.values = read_words(folder + "/values.bin");
  frame.scales = read_floats(folder + "/scales.bin");
  frame.shells = read_words(folder + "/shells.bin");
  if (frame.receiver_positions.size() != 4ull * frame.pixel_count() || frame.receiver_normals.size() != 4ull * frame.pixel_count()) {
    throw std::runtime_error(folder + ": receiver arrays do not match width x height");
  }
  if (frame.objects.size() % lpi_record::kWords != 0) {
    throw std::runtime_error(folder + "/objects.bin: not whole records of " + std::to_string(lpi_record::kWords) + " words");
  }
  if (frame.lights.size() % lpi_light::kFloats != 0) {
    throw std::runtime_error(folder + "/lights.bin: not whole records of " + std::to_string(lpi_light::kFloats) + " floats");
  }
  // Every record's lights within lights.bin (values and tables are the writer's; a shader reads them).
  const size_t light_count = frame.lights.size() / lpi_light::kFloats;
  for (uint32_t object = 0; object < frame.object_count(); ++object) {
    const uint32_t* record = frame.objects.data() + object * lpi_record::kWords;
    if (static_cast<size_t>(record[lpi_record::kFirstLight]) + record[lpi_record::kLightCount] > light_count) {
      throw std::runtime_error(folder + "/objects.bin: object " + std::to_string(object) + " reads lights beyond lights.bin");
    }
  }
  return frame;
}

}  // namespace causticbench
