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
  require(frame.passes.size() % F::kPassWords == 0 && frame.views.size() == 2 * F::kViewFloats * frame.pass_count() &&
              frame.strengths.size() == 4 * size_t(frame.pass_count()),
          where, "views, strengths and passes disagree");
  require(frame.vertices.size() % (3 * F::kVertexFloats) == 0, where, "vertices.bin is not whole triangles");
  require(frame.objects.size() % F::kObjectFloats == 0, where, "objects.bin is not whole objects");
  require(frame.splat <= 2 && frame.plane_hit <= 1 && frame.search_iterations <= 64 && frame.refraction <= 2, where,
          "splat, hit_position, search_iterations or refraction out of range");
  require(frame.splat_radius > 0.0f && frame.splat_photons > 0.0f && frame.max_splat_radius >= 0.5f, where,
          "splat radii and photon counts must be positive");
  for (uint32_t vertex = 0; vertex < frame.vertex_count(); ++vertex) {
    const float object = frame.vertices[F::kVertexFloats * vertex + 3];
    require(object >= 0.0f && object < float(frame.object_count()) && object == float(uint32_t(object)), where,
            "vertex " + std::to_string(vertex) + " names no object of objects.bin");
  }
  for (uint32_t pass = 0; pass < frame.pass_count(); ++pass) {
    const uint32_t* words = &frame.passes[F::kPassWords * pass];
    const uint64_t n = words[0], p = words[3];
    const std::string name = "pass " + std::to_string(pass);
    require(n >= 2 && n <= 16384 && p >= 1 && p <= 16384, where, name + ": map or photon-buffer resolution out of range");
    require(words[1] + n * n <= frame.texel_count(), where, name + "'s caustic map is beyond measures.bin");
    require(words[2] + p * p <= frame.photon_count(), where, name + "'s photon buffer is beyond photon_measures.bin");
    require(words[4] < frame.object_count(), where, name + "'s object is beyond objects.bin");
    for (int view = 0; view < 2; ++view) {
      const float* record = &frame.views[F::kViewFloats * (2 * pass + view)];
      require(record[7] > 0.0f, where, name + ": a window of no extent");
      require(record[16] < record[17] && (record[3] != 0.0f || record[16] > 0.0f), where,
              name + ": a depth range that is empty (or starts at the eye of a perspective view)");
    }
  }
}

void write_caustic_mapping_frame_data(const CausticMappingFrameData& frame, const std::string& folder) {
  write_floats(folder + "/receiver_positions.bin", frame.receiver_positions);
  write_floats(folder + "/receiver_normals.bin", frame.receiver_normals);
  write_floats(folder + "/vertices.bin", frame.vertices);
  write_floats(folder + "/objects.bin", frame.objects);
  write_floats(folder + "/views.bin", frame.views);
  write_words(folder + "/passes.bin", frame.passes);
  write_floats(folder + "/strengths.bin", frame.strengths);
  write_floats(folder + "/measures.bin", frame.measures);
  write_floats(folder + "/photon_measures.bin", frame.photon_measures);
  std::ostringstream text;
  text.precision(9);
  text << "width " << frame.width << "\nheight " << frame.height << "\nsearch_iterations " << frame.search_iterations
       << "\nplane_hit " << frame.plane_hit << "\nsplat " << frame.splat << "\nrefraction " << frame.refraction
       << "\nsplat_radius " << frame.splat_radius << "\nsplat_photons " << frame.splat_photons << "\nmax_splat_radius "
       << frame.max_splat_radius << "\n";
  // Last: its presence marks a complete frame.
  write_dump_bytes(folder + "/caustic_mapping_frame.txt", text.str().data(), text.str().size());
}

CausticMappingFrameData read_caustic_mapping_frame_data(const std::string& folder) {
  CausticMappingFrameData frame;
  std::map<std::string, double> values =
      read_dump_fields(folder + "/caustic_mapping_frame.txt", {"width", "height", "search_iterations", "plane_hit", "splat",
                                                               "refraction", "splat_radius", "splat_photons",
                                                               "max_splat_radius"});
  frame.width = static_cast<uint32_t>(values["width"]);
  frame.height = static_cast<uint32_t>(values["height"]);
  frame.search_iterations = static_cast<uint32_t>(values["search_iterations"]);
  frame.plane_hit = static_cast<uint32_t>(values["plane_hit"]);
  frame.splat = static_cast<uint32_t>(values["splat"]);
  frame.refraction = static_cast<uint32_t>(values["refraction"]);
  frame.splat_radius = static_cast<float>(values["splat_radius"]);
  frame.splat_photons = static_cast<float>(values["splat_photons"]);
  frame.max_splat_radius = static_cast<float>(values["max_splat_radius"]);
  frame.receiver_positions = read_floats(folder + "/receiver_positions.bin");
  frame.receiver_normals = read_floats(folder + "/receiver_normals.bin");
  frame.vertices = read_floats(folder + "/vertices.bin");
  frame.objects = read_floats(folder + "/objects.bin");
  frame.views = read_floats(folder + "/views.bin");
  frame.passes = read_words(folder + "/passes.bin");
  frame.strengths = read_floats(folder + "/strengths.bin");
  frame.measures = read_floats(folder + "/measures.bin");
  frame.photon_measures = read_floats(folder + "/photon_measures.bin");
  check_frame_data(frame, folder);
  return frame;
}

}  // namespace causticbench
