#include "methods/prt/frame_data.h"

#include <map>
#include <sstream>
#include <stdexcept>

namespace causticbench {

namespace {

void require(bool condition, const std::string& where, const std::string& what) {
  if (!condition) throw std::runtime_error(where + ": " + what);
}

uint32_t word(const PrtFrameData& frame, uint32_t object, uint32_t k) {
  return frame.objects[static_cast<size_t>(object) * prt_record::kWords + k];
}

}  // namespace

uint32_t PrtFrameData::cells(uint32_t object) const {
  const uint32_t resolution = word(*this, object, prt_record::kResolution);
  return resolution * resolution * resolution;
}

uint64_t PrtFrameData::incident_floats() const {
  uint64_t total = 0;
  for (uint32_t object = 0; object < object_count(); ++object) total += uint64_t(cells(object)) * 3 * coefficients();
  return total;
}

void check_prt_frame_data(const PrtFrameData& frame, const std::string& where) {
  const size_t pixels = frame.pixel_count();
  require(frame.receiver_positions.size() == 4 * pixels && frame.receiver_normals.size() == 4 * pixels, where,
          "receiver arrays do not match width x height");
  require(frame.bands >= 1 && frame.bands <= 10, where, "bands out of range (1 .. 10)");
  require(frame.precision <= 1, where, "precision out of range (0 float32, 1 float16)");
  require(frame.objects.size() % prt_record::kWords == 0, where, "objects.bin is not whole records");
  const uint64_t n2 = frame.coefficients();
  require(frame.basis_factors.size() == 3 * n2 && frame.clamped_cosines.size() == frame.bands, where,
          "the basis tables do not match bands");
  require(frame.lighting.size() == frame.object_count() * 3 * n2, where, "lighting.bin is not 3 x bands^2 an object");
  uint64_t elements = 0, incident = 0;
  for (uint32_t object = 0; object < frame.object_count(); ++object) {
    const uint32_t resolution = word(frame, object, prt_record::kResolution);
    require(resolution >= 2 && resolution <= 1024, where, "object " + std::to_string(object) + ": resolution out of range");
    require(word(frame, object, prt_record::kMatrices) == elements && word(frame, object, prt_record::kLighting) == object * 3 * n2 &&
                word(frame, object, prt_record::kIncident) == incident,
            where, "object " + std::to_string(object) + ": its matrices, lighting or incident field do not follow the previous object's");
    elements += uint64_t(frame.cells(object)) * 3 * n2 * n2;
    incident += uint64_t(frame.cells(object)) * 3 * n2;
  }
  // Element and float indices are 32-bit on the device.
  require(elements < (uint64_t(1) << 32) && incident < (uint64_t(1) << 32), where,
          "the matrices hold more than 2^32 entries, beyond the device's indices");
  const uint64_t words = frame.precision == 0 ? elements : (elements + 1) / 2;
  require(frame.matrices.size() == words, where, "matrices.bin does not hold the objects' cells x 3 x bands^4 entries");
}

void write_prt_frame_data(const PrtFrameData& frame, const std::string& folder) {
  write_floats(folder + "/receiver_positions.bin", frame.receiver_positions);
  write_floats(folder + "/receiver_normals.bin", frame.receiver_normals);
  write_words(folder + "/objects.bin", frame.objects);
  write_floats(folder + "/lighting.bin", frame.lighting);
  write_words(folder + "/matrices.bin", frame.matrices);
  write_floats(folder + "/basis_factors.bin", frame.basis_factors);
  write_floats(folder + "/clamped_cosines.bin", frame.clamped_cosines);
  std::ostringstream text;
  text << "width " << frame.width << "\nheight " << frame.height << "\nbands " << frame.bands << "\nprecision "
       << frame.precision << "\n";
  // Last: its presence marks a complete frame.
  write_dump_bytes(folder + "/prt_frame.txt", text.str().data(), text.str().size());
}

PrtFrameData read_prt_frame_data(const std::string& folder) {
  PrtFrameData frame;
  std::map<std::string, double> values =
      read_dump_fields(folder + "/prt_frame.txt", {"width", "height", "bands", "precision"});
  frame.width = static_cast<uint32_t>(values["width"]);
  frame.height = static_cast<uint32_t>(values["height"]);
  frame.bands = static_cast<uint32_t>(values["bands"]);
  frame.precision = static_cast<uint32_t>(values["precision"]);
  frame.receiver_positions = read_floats(folder + "/receiver_positions.bin");
  frame.receiver_normals = read_floats(folder + "/receiver_normals.bin");
  frame.objects = read_words(folder + "/objects.bin");
  frame.lighting = read_floats(folder + "/lighting.bin");
  frame.matrices = read_words(folder + "/matrices.bin");
  frame.basis_factors = read_floats(folder + "/basis_factors.bin");
  frame.clamped_cosines = read_floats(folder + "/clamped_cosines.bin");
  check_prt_frame_data(frame, folder);
  return frame;
}

}  // namespace causticbench
