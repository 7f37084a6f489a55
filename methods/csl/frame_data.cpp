#include "methods/csl/frame_data.h"

#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

namespace causticbench {

namespace {

void require(bool condition, const std::string& where, const std::string& what) {
  if (!condition) throw std::runtime_error(where + ": " + what);
}

}  // namespace

void check_frame_data(const CslFrameData& frame, const std::string& where) {
  using F = CslFrameData;
  const size_t pixels = frame.pixel_count();
  require(frame.receiver_positions.size() == 4 * pixels && frame.receiver_normals.size() == 4 * pixels, where,
          "receiver arrays do not match width x height");
  require(frame.object_lights.size() % 2 == 0 && frame.objects.size() == F::kObjectFloats * frame.object_count(), where,
          "objects and object_lights disagree");
  require(frame.light_images.size() % F::kLightWords == 0 && frame.lights.size() == F::kLightFloats * frame.light_count(),
          where, "lights and light_images disagree");
  require(frame.images.size() % F::kImageWords == 0 && frame.image_scalars.size() == F::kImageFloats * frame.image_count(),
          where, "images and image_scalars disagree");
  require(frame.on_axis <= 1 && frame.intensity_correction <= 1, where, "on_axis and intensity_correction are 0 or 1");
  for (uint32_t object = 0; object < frame.object_count(); ++object) {
    const uint64_t first = frame.object_lights[2 * object], count = frame.object_lights[2 * object + 1];
    require(first + count <= frame.light_count(), where, "object " + std::to_string(object) + "'s spot lights are beyond the list");
  }
  for (uint32_t light = 0; light < frame.light_count(); ++light) {
    const uint32_t* words = &frame.light_images[F::kLightWords * light];
    const float channels = frame.lights[F::kLightFloats * light + 15];
    require(words[0] <= F::kMaxSources && (channels == 1.0f || channels == 3.0f), where,
            "spot light " + std::to_string(light) + ": up to 3 sources and 1 or 3 channels");
    for (uint32_t s = 0; s < words[0]; ++s) {
      require(words[1 + s] < frame.image_count(), where, "spot light " + std::to_string(light) + " reads a missing image");
    }
  }
  for (uint32_t image = 0; image < frame.image_count(); ++image) {
    const uint32_t* words = &frame.images[F::kImageWords * image];
    const uint64_t size = words[1], channels = words[2], elements = size * size * channels;
    const uint64_t texel_words = words[3] == 1 ? (elements + 1) / 2 : elements;
    require(size > 0 && (channels == 1 || channels == 3) && words[3] <= 1 && words[5] > 0, where,
            "image " + std::to_string(image) + ": size, channels, precision or bins out of range");
    require(words[0] + texel_words <= frame.texels.size(), where, "image " + std::to_string(image) + "'s texels are beyond texels.bin");
    require(words[4] + 2ull * (words[5] + 1) * channels <= frame.radial.size(), where,
            "image " + std::to_string(image) + "'s tables are beyond radial.bin");
  }
}

void write_csl_frame_data(const CslFrameData& frame, const std::string& folder) {
  write_floats(folder + "/receiver_positions.bin", frame.receiver_positions);
  write_floats(folder + "/receiver_normals.bin", frame.receiver_normals);
  write_floats(folder + "/objects.bin", frame.objects);
  write_words(folder + "/object_lights.bin", frame.object_lights);
  write_floats(folder + "/lights.bin", frame.lights);
  write_words(folder + "/light_images.bin", frame.light_images);
  write_words(folder + "/images.bin", frame.images);
  write_floats(folder + "/image_scalars.bin", frame.image_scalars);
  write_words(folder + "/texels.bin", frame.texels);
  write_floats(folder + "/radial.bin", frame.radial);
  std::ostringstream text;
  text << "width " << frame.width << "\nheight " << frame.height << "\nintensity_correction " << frame.intensity_correction
       << "\non_axis " << frame.on_axis << "\n";
  // Last: its presence marks a complete frame.
  write_dump_bytes(folder + "/csl_frame.txt", text.str().data(), text.str().size());
}

CslFrameData read_csl_frame_data(const std::string& folder) {
  CslFrameData frame;
  std::map<std::string, double> values =
      read_dump_fields(folder + "/csl_frame.txt", {"width", "height", "intensity_correction", "on_axis"});
  frame.width = static_cast<uint32_t>(values["width"]);
  frame.height = static_cast<uint32_t>(values["height"]);
  frame.intensity_correction = static_cast<uint32_t>(values["intensity_correction"]);
  frame.on_axis = static_cast<uint32_t>(values["on_axis"]);
  frame.receiver_positions = read_floats(folder + "/receiver_positions.bin");
  frame.receiver_normals = read_floats(folder + "/receiver_normals.bin");
  frame.objects = read_floats(folder + "/objects.bin");
  frame.object_lights = read_words(folder + "/object_lights.bin");
  frame.lights = read_floats(folder + "/lights.bin");
  frame.light_images = read_words(folder + "/light_images.bin");
  frame.images = read_words(folder + "/images.bin");
  frame.image_scalars = read_floats(folder + "/image_scalars.bin");
  frame.texels = read_words(folder + "/texels.bin");
  frame.radial = read_floats(folder + "/radial.bin");
  check_frame_data(frame, folder);
  return frame;
}

}  // namespace causticbench
