#include "methods/pinhole/frame_data.h"

#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

namespace causticbench {

void write_frame_data(const PinholeFrameData& frame, const std::string& folder) {
  write_floats(folder + "/receiver_positions.bin", frame.receiver_positions);
  write_floats(folder + "/receiver_normals.bin", frame.receiver_normals);
  write_floats(folder + "/sample_positions.bin", frame.sample_positions);
  write_floats(folder + "/sample_normals.bin", frame.sample_normals);
  write_floats(folder + "/materials.bin", frame.materials);
  write_floats(folder + "/cube_map.bin", frame.cube_map);
  write_floats(folder + "/differentials.bin", frame.differentials);
  if (frame.own_filter) write_floats(folder + "/filter_levels.bin", frame.filter_levels);
  std::ostringstream text;
  text.precision(9);
  text << "width " << frame.width << "\nheight " << frame.height << "\nresolution " << frame.resolution << "\nepsilon "
       << frame.epsilon << "\narea " << frame.area << "\nattenuation " << frame.attenuation << "\nfresnel "
       << frame.fresnel << "\nrefraction " << frame.refraction << "\nfiltering " << frame.filtering
       << "\nfootprint_radius " << frame.footprint_radius << "\nown_filter " << frame.own_filter << "\n";
  // Last: its presence marks a complete frame.
  write_dump_bytes(folder + "/frame.txt", text.str().data(), text.str().size());
}

PinholeFrameData read_frame_data(const std::string& folder) {
  PinholeFrameData frame;
  std::map<std::string, double> values =
      read_dump_fields(folder + "/frame.txt", {"width", "height", "resolution", "epsilon", "area", "attenuation",
                                               "fresnel", "refraction", "filtering", "footprint_radius"});
  frame.width = static_cast<uint32_t>(values["width"]);
  frame.height = static_cast<uint32_t>(values["height"]);
  frame.resolution = static_cast<int32_t>(values["resolution"]);
  frame.epsilon = static_cast<float>(values["epsilon"]);
  frame.area = static_cast<float>(values["area"]);
  frame.attenuation = static_cast<uint32_t>(values["attenuation"]);
  frame.fresnel = static_cast<uint32_t>(values["fresnel"]);
  frame.refraction = static_cast<uint32_t>(values["refraction"]);
  frame.filtering = static_cast<uint32_t>(values["filtering"]);
  frame.footprint_radius = static_cast<float>(values["footprint_radius"]);
  // Optional: dumps from before the own filter used the device's sampler.
  frame.own_filter = values.count("own_filter") ? static_cast<uint32_t>(values["own_filter"]) : 0u;
  if (frame.own_filter) frame.filter_levels = read_floats(folder + "/filter_levels.bin");
  frame.receiver_positions = read_floats(folder + "/receiver_positions.bin");
  frame.receiver_normals = read_floats(folder + "/receiver_normals.bin");
  frame.sample_positions = read_floats(folder + "/sample_positions.bin");
  frame.sample_normals = read_floats(folder + "/sample_normals.bin");
  frame.materials = read_floats(folder + "/materials.bin");
  frame.cube_map = read_floats(folder + "/cube_map.bin");
  frame.differentials = read_floats(folder + "/differentials.bin");
  if (frame.filtering != 0 && frame.differentials.size() != 4ull * frame.sample_positions.size()) {
    throw std::runtime_error(folder + "/differentials.bin: expected 16 floats per sample when filtering");
  }
  if (frame.receiver_positions.size() != 4ull * frame.pixel_count() || frame.receiver_normals.size() != 4ull * frame.pixel_count()) {
    throw std::runtime_error(folder + ": receiver arrays do not match width x height");
  }
  if (frame.cube_map.size() != 18ull * frame.resolution * frame.resolution) {
    throw std::runtime_error(folder + "/cube_map.bin: does not match the resolution");
  }
  return frame;
}

}  // namespace causticbench
