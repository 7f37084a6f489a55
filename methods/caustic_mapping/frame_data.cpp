#include "methods/caustic_mapping/frame_data.h"

#include <map>
#include <sstream>
#include <stdexcept>

namespace causticbench {

namespace {

void require(bool condition, const std::string& where, const std::string& what) {
  if (!condition) throw std::runtime_error(where + ": " + what);
}

}  // namespace

void check_frame_data(const CausticMappingFrameData& frame, const std::string& where) {
  using F = CausticMappingFrameData;
  const size_t pixels = frame.pixel_count();
  require(frame.receiver_positions.size() == 4 * pixels && frame.receiver_normals.size() == 4 * pixels, where,
          "receiver arrays do not match width x height");
  require(frame.passes.size() % F::kPassWords == 0 && frame.views.size() == F::kViewFloats * frame.pass_count(), where,
          "views and passes disagree");
  require(frame.receivers.size() == F::kReceiverFloats * frame.measures.size(), where,
          "receivers.bin and measures.bin disagree");
  require(frame.photons.size() % F::kPhotonFloats == 0, where, "photons.bin is not whole photons");
  require(frame.splat <= 2 && frame.plane_hit <= 1 && frame.search_iterations <= 64, where,
          "splat, hit_position or search_iterations out of range");
  require(frame.splat_radius > 0.0f && frame.splat_photons > 0.0f && frame.max_splat_radius >= 0.5f, where,
          "splat radii and photon counts must be positive");
  for (uint32_t pass = 0; pass < frame.pass_count(); ++pass) {
    const uint32_t* words = &frame.passes[F::kPassWords * pass];
    const uint64_t n = words[0];
    require(n >= 2 && n <= 16384, where, "pass " + std::to_string(pass) + ": map resolution out of range");
    require(words[1] + n * n <= frame.texel_count(), where, "pass " + std::to_string(pass) + "'s maps are beyond measures.bin");
    require(uint64_t(words[2]) + words[3] <= frame.photon_count(), where,
            "pass " + std::to_string(pass) + "'s photons are beyond photons.bin");
    const float* view = &frame.views[F::kViewFloats * pass];
    require(view[7] > 0.0f, where, "pass " + std::to_string(pass) + ": a window of no extent");
  }
}

void write_caustic_mapping_frame_data(const CausticMappingFrameData& frame, const std::string& folder) {
  write_floats(folder + "/receiver_positions.bin", frame.receiver_positions);
  write_floats(folder + "/receiver_normals.bin", frame.receiver_normals);
  write_floats(folder + "/views.bin", frame.views);
  write_words(folder + "/passes.bin", frame.passes);
  write_floats(folder + "/receivers.bin", frame.receivers);
  write_floats(folder + "/measures.bin", frame.measures);
  write_floats(folder + "/photons.bin", frame.photons);
  std::ostringstream text;
  text.precision(9);
  text << "width " << frame.width << "\nheight " << frame.height << "\nsearch_iterations " << frame.search_iterations
       << "\nplane_hit " << frame.plane_hit << "\nsplat " << frame.splat << "\nsplat_radius " << frame.splat_radius
       << "\nsplat_photons " << frame.splat_photons << "\nmax_splat_radius " << frame.max_splat_radius << "\n";
  // Last: its presence marks a complete frame.
  write_dump_bytes(folder + "/caustic_mapping_frame.txt", text.str().data(), text.str().size());
}

CausticMappingFrameData read_caustic_mapping_frame_data(const std::string& folder) {
  CausticMappingFrameData frame;
  std::map<std::string, double> values =
      read_dump_fields(folder + "/caustic_mapping_frame.txt", {"width", "height", "search_iterations", "plane_hit", "splat",
                                                               "splat_radius", "splat_photons", "max_splat_radius"});
  frame.width = static_cast<uint32_t>(values["width"]);
  frame.height = static_cast<uint32_t>(values["height"]);
  frame.search_iterations = static_cast<uint32_t>(values["search_iterations"]);
  frame.plane_hit = static_cast<uint32_t>(values["plane_hit"]);
  frame.splat = static_cast<uint32_t>(values["splat"]);
  frame.splat_radius = static_cast<float>(values["splat_radius"]);
  frame.splat_photons = static_cast<float>(values["splat_photons"]);
  frame.max_splat_radius = static_cast<float>(values["max_splat_radius"]);
  frame.receiver_positions = read_floats(folder + "/receiver_positions.bin");
  frame.receiver_normals = read_floats(folder + "/receiver_normals.bin");
  frame.views = read_floats(folder + "/views.bin");
  frame.passes = read_words(folder + "/passes.bin");
  frame.receivers = read_floats(folder + "/receivers.bin");
  frame.measures = read_floats(folder + "/measures.bin");
  frame.photons = read_floats(folder + "/photons.bin");
  check_frame_data(frame, folder);
  return frame;
}

}  // namespace causticbench
