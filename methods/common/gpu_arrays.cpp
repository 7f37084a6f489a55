#include "methods/common/gpu_arrays.h"

#include "methods/frame_dump.h"

namespace causticbench {

void fill_receiver_arrays(const GBuffer& gbuffer, std::vector<float>& positions, std::vector<float>& normals) {
  positions.resize(gbuffer.pixel_count() * 4);
  normals.resize(gbuffer.pixel_count() * 4);
  for (size_t pixel = 0; pixel < gbuffer.pixel_count(); ++pixel) {
    const Vec3& p = gbuffer.position[pixel];
    const Vec3& n = gbuffer.normal[pixel];
    float* position = &positions[4 * pixel];
    float* normal = &normals[4 * pixel];
    position[0] = p.x, position[1] = p.y, position[2] = p.z, position[3] = gbuffer.receiver[pixel] ? 1.0f : 0.0f;
    normal[0] = n.x, normal[1] = n.y, normal[2] = n.z, normal[3] = 0.0f;
  }
}

Image image_of_rgba(int width, int height, const std::vector<float>& rgba) {
  Image result(width, height, 3);
  for (size_t pixel = 0; pixel < result.pixel_count(); ++pixel)
    result.set_rgb(pixel, Color(rgba[4 * pixel], rgba[4 * pixel + 1], rgba[4 * pixel + 2]));
  return result;
}

std::vector<float> rgba_of(const Image& image) {
  std::vector<float> rgba(image.pixel_count() * 4, 0.0f);
  for (size_t pixel = 0; pixel < image.pixel_count(); ++pixel)
    for (int c = 0; c < 3; ++c) rgba[4 * pixel + c] = image.at(pixel, c);
  return rgba;
}

void write_dump_irradiance(const std::string& folder, const std::string& backend, const Image& output) {
  write_floats(folder + "/" + backend + "_irradiance.bin", rgba_of(output));
}

}  // namespace causticbench
