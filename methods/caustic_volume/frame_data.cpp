#include "methods/caustic_volume/frame_data.h"

#include <map>
#include <sstream>
#include <stdexcept>

namespace causticbench {

namespace {

void require(bool condition, const std::string& where, const std::string& what) {
  if (!condition) throw std::runtime_error(where + ": " + what);
}

}  // namespace

void check_frame_data(const CausticVolumeFrameData& frame, const std::string& where) {
  const size_t pixels = frame.pixel_count();
  require(frame.receiver_positions.size() == 4 * pixels && frame.receiver_normals.size() == 4 * pixels &&
              frame.receiver_objects.size() == pixels,
          where, "receiver arrays do not match width x height");
  require(frame.intensity <= 1, where, "intensity out of range (0 interpolated, 1 constant)");
  require(frame.volumes.size() % CausticVolumeFrameData::kVolumeFloats == 0, where, "volumes.bin is not whole volumes");
  require(frame.footprints.size() % 12 == 0, where, "footprints.bin is not whole triangles");
  for (uint32_t vertex = 0; vertex < frame.footprint_vertex_count(); ++vertex) {
    const float volume = frame.footprints[4 * vertex + 2];
    require(volume >= 0.0f && volume < float(frame.volume_count()) && volume == float(uint32_t(volume)), where,
            "footprint vertex " + std::to_string(vertex) + " names no volume of volumes.bin");
  }
}

void write_caustic_volume_frame_data(const CausticVolumeFrameData& frame, const std::string& folder) {
  write_floats(folder + "/receiver_positions.bin", frame.receiver_positions);
  write_floats(folder + "/receiver_normals.bin", frame.receiver_normals);
  write_floats(folder + "/receiver_objects.bin", frame.receiver_objects);
  write_floats(folder + "/volumes.bin", frame.volumes);
  write_floats(folder + "/footprints.bin", frame.footprints);
  std::ostringstream text;
  text << "width " << frame.width << "\nheight " << frame.height << "\nintensity " << frame.intensity << "\n";
  // Last: its presence marks a complete frame.
  write_dump_bytes(folder + "/caustic_volume_frame.txt", text.str().data(), text.str().size());
}

CausticVolumeFrameData read_caustic_volume_frame_data(const std::string& folder) {
  CausticVolumeFrameData frame;
  std::map<std::string, double> values =
      read_dump_fields(folder + "/caustic_volume_frame.txt", {"width", "height", "intensity"});
  frame.width = static_cast<uint32_t>(values["width"]);
  frame.height = static_cast<uint32_t>(values["height"]);
  frame.intensity = static_cast<uint32_t>(values["intensity"]);
  frame.receiver_positions = read_floats(folder + "/receiver_positions.bin");
  frame.receiver_normals = read_floats(folder + "/receiver_normals.bin");
  frame.receiver_objects = read_floats(folder + "/receiver_objects.bin");
  frame.volumes = read_floats(folder + "/volumes.bin");
  frame.footprints = read_floats(folder + "/footprints.bin");
  check_frame_data(frame, folder);
  return frame;
}

}  // namespace causticbench
