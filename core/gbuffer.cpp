#include "core/gbuffer.h"

#include <algorithm>
#include <stdexcept>

#include <fmt/format.h>

#include "core/parallel.h"

namespace causticbench {

size_t GBuffer::receiver_count() const {
  size_t count = 0;
  for (uint8_t r : receiver) count += r;
  return count;
}

void GBuffer::clear_outside_receivers(Image& image) const {
  for (size_t pixel = 0; pixel < pixel_count(); ++pixel) {
    if (!receiver[pixel]) image.set_rgb(pixel, Color(0.0f));
  }
}

const std::vector<std::string>& GBuffer::channel_names() {
  static const std::vector<std::string> names = {"position.X", "position.Y", "position.Z", "normal.X",
                                                 "normal.Y",   "normal.Z",   "albedo.R",   "albedo.G",
                                                 "albedo.B",   "object",     "receiver",   "footprint"};
  return names;
}

Image GBuffer::read_image(const std::string& path) {
  std::vector<std::string> names;
  const Image stored = read_exr(path, &names);
  const std::vector<std::string>& wanted = channel_names();
  // Unnamed files: OpenImageIO's defaults for channel i.
  const std::vector<std::string> unnamed = {"R", "G", "B", "A"};
  Image image(stored.width(), stored.height(), static_cast<int>(wanted.size()));
  for (size_t c = 0; c < wanted.size(); ++c) {
    const std::string fallback = c < unnamed.size() ? unnamed[c] : "channel" + std::to_string(c);
    auto found = std::find(names.begin(), names.end(), wanted[c]);
    if (found == names.end()) found = std::find(names.begin(), names.end(), fallback);
    if (found == names.end())
      throw std::runtime_error(fmt::format("{}: a G-buffer without channel {} (nor {})", path, wanted[c], fallback));
    const int from = static_cast<int>(found - names.begin());
    for (size_t pixel = 0; pixel < image.pixel_count(); ++pixel) image.at(pixel, static_cast<int>(c)) = stored.at(pixel, from);
  }
  return image;
}

Image GBuffer::to_image() const {
  Image image(width, height, 12);
  for (size_t i = 0; i < pixel_count(); ++i) {
    for (int c = 0; c < 3; ++c) {
      image.at(i, c) = position[i][c];
      image.at(i, 3 + c) = normal[i][c];
      image.at(i, 6 + c) = albedo[i][c];
    }
    image.at(i, 9) = static_cast<float>(object[i]);
    image.at(i, kReceiverChannel) = receiver[i];
    image.at(i, 11) = footprint[i];
  }
  return image;
}

GBuffer render_gbuffer(const Tracer& tracer, float offset_x, float offset_y) {
  const SceneFrame& frame = tracer.frame();
  GBuffer gbuffer;
  gbuffer.width = frame.camera.width();
  gbuffer.height = frame.camera.height();
  size_t count = gbuffer.pixel_count();
  gbuffer.position.assign(count, Vec3(0.0f));
  gbuffer.normal.assign(count, Vec3(0.0f));
  gbuffer.albedo.assign(count, Color(0.0f));
  gbuffer.object.assign(count, -1);
  gbuffer.receiver.assign(count, 0);
  gbuffer.footprint.assign(count, 0.0f);
  const Vec3 view_axis = frame.camera.primary_ray(gbuffer.width / 2, gbuffer.height / 2).direction;
  parallel_blocks(count, 1024, [&](size_t begin, size_t end, size_t) {
    for (size_t i = begin; i < end; ++i) {
      int x = static_cast<int>(i % gbuffer.width), y = static_cast<int>(i / gbuffer.width);
      Ray ray = frame.camera.primary_ray(x, y, offset_x, offset_y);
      SurfaceHit hit;
      if (!tracer.intersect(ray, hit)) continue;
      const Material& material = frame.scene->objects[hit.object].material;
      Vec3 normal = hit.shading_normal;
      if (glm::dot(normal, ray.direction) > 0.0f) normal = -normal;
      gbuffer.position[i] = hit.position;
      gbuffer.normal[i] = normal;
      gbuffer.object[i] = hit.object;
      if (material.receives_caustics()) {
        gbuffer.receiver[i] = 1;
        gbuffer.albedo[i] = material.albedo;
      }
      float along_view = hit.t * std::abs(glm::dot(ray.direction, view_axis));
      float cosine = std::max(0.05f, std::abs(glm::dot(normal, ray.direction)));
      gbuffer.footprint[i] = frame.camera.pixel_footprint(along_view) / std::sqrt(cosine);
    }
  });
  return gbuffer;
}

}  // namespace causticbench
