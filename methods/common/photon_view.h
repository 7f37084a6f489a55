// Whether the camera sees where a photon landed: the one definition of "in view" for the estimators
// that credit photons to pixels (the reference's footprint tally) and for the photon map's count of the
// flux its gathers miss (its lost flux).
#pragma once

#include <optional>

#include "core/camera.h"
#include "core/photon_tracer.h"
#include "core/tracer.h"

namespace causticbench {

// Whether the camera sees the photon at `image` (its projection, CameraFrame::project): it arrived on the
// side of its surface that faces the camera and a shadow ray from there to the camera is free. For a
// caller that tests the projected pixel first (the reference's tally, where most photons land outside
// the receivers' pixels), without projecting twice.
bool camera_sees(const CameraFrame::ImagePoint& image, const Tracer& tracer, const Photon& photon);

// The pixel whose footprint holds the photon when the camera sees it (camera_sees); nothing otherwise
// (behind the camera, outside the image, the far side of the surface, hidden). Does not check the
// pixel's mask.
std::optional<CameraFrame::ImagePoint> photon_seen_by_camera(const CameraFrame& camera, const Tracer& tracer,
                                                             const Photon& photon);

}  // namespace causticbench
