#include "methods/common/photon_view.h"

namespace causticbench {

std::optional<CameraFrame::ImagePoint> photon_seen_by_camera(const CameraFrame& camera, const Tracer& tracer,
                                                             const Photon& photon) {
  std::optional<CameraFrame::ImagePoint> image = camera.project(photon.position, photon.normal);
  if (!image) return std::nullopt;
  // E_c is the irradiance on the side of the surface the camera sees, and only where it sees it.
  if (glm::dot(photon.normal, image->to_camera) <= 0.0f) return std::nullopt;
  const float epsilon = tracer.epsilon();
  const Vec3 origin = photon.position + photon.normal * epsilon;
  if (image->distance > 2.0f * epsilon && tracer.occluded(origin, image->to_camera, image->distance - 2.0f * epsilon))
    return std::nullopt;
  return image;
}

}  // namespace causticbench
