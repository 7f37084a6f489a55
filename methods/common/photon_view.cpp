#include "methods/common/photon_view.h"

namespace causticbench {

bool camera_sees(const CameraFrame::ImagePoint& image, const Tracer& tracer, const Photon& photon) {
  // E_c is the irradiance on the side of the surface the camera sees, and only where it sees it.
  if (glm::dot(photon.normal, image.to_camera) <= 0.0f) return false;
  const float epsilon = tracer.epsilon();
  const Vec3 origin = photon.position + photon.normal * epsilon;
  return !(image.distance > 2.0f * epsilon && tracer.occluded(origin, image.to_camera, image.distance - 2.0f * epsilon));
}

std::optional<CameraFrame::ImagePoint> photon_seen_by_camera(const CameraFrame& camera, const Tracer& tracer,
                                                             const Photon& photon) {
  std::optional<CameraFrame::ImagePoint> image = camera.project(photon.position, photon.normal);
  if (!image || !camera_sees(*image, tracer, photon)) return std::nullopt;
  return image;
}

}  // namespace causticbench
