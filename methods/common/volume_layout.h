// Where the caustic of one object is sampled, and how (Wyman 2003, Section 4.2): the layout of the
// sample points in a ball around the object, the track-length estimator that turns photon segments
// into irradiance at those points, and the interpolation that reads them back. Two layouts:
// grid_layout.h (a uniform grid of cells) and shell_layout.h (concentric shells, geodesic vertices).
//
// The estimator. A photon of power P that travels a length l through a region of volume V adds
// P l / V to the region's mean fluence rate; weighting each piece of track by the cosine between the
// direction of travel and a surface normal gives the mean irradiance on that surface (the
// track-length estimator of transport theory). The paper's "contribution as if it hit a surface at
// the sample point S with normal O_center - S", normalised "by how many photons would have hit the
// cell without O present", is this estimator with the cosine to the normal facing the object's
// centre; photons carry the flux of a unit-irradiance light divided by the number emitted, so a
// sample holds caustic irradiance per unit light irradiance, exactly.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/math.h"
#include "core/photon_tracer.h"

namespace causticbench {

// paper: one RGB irradiance per sample, on the surface facing the object's centre, corrected by the
// cosine to the receiver's normal (Section 3.2). vector: the RGB vector irradiance (three vectors,
// nine values), shaded as max(0, n . E_c) per channel: exact wherever a cell's light comes from one side.
enum class Orientation { paper, vector };
inline int channel_count(Orientation orientation) { return orientation == Orientation::paper ? 3 : 9; }

// Up to eight sample points and their interpolation weights (non-negative, summing to one).
struct Stencil {
  int count = 0;
  uint32_t points[8];
  float weights[8];
};

class VolumeLayout {
 public:
  virtual ~VolumeLayout() = default;
  // Ball of the samples, in the build space of the object: centre and radius.
  Vec3 center() const { return center_; }
  float radius() const { return radius_; }
  virtual size_t points() const = 0;
  // Adds the segment's contribution to `sums` (points() * channel_count(orientation) values), before
  // normalise(). The segment is in build space; pieces outside the layout's region (the ball for
  // shells, the cube around it for the grid) add nothing.
  virtual void deposit(const PathSegment& segment, Orientation orientation, float* sums) const = 0;
  // Turns the sums of power x length (x cosine) into irradiance: divides each point's values by the
  // volume its estimator kernel integrates to, and by the number of photons emitted.
  virtual void normalise(double photons_emitted, Orientation orientation, double* values) const = 0;
  // Interpolation stencil at `position` (build space, inside the ball or on its surface).
  virtual Stencil stencil(const Vec3& position) const = 0;
  // Bytes of the layout's own tables (not the values).
  virtual size_t memory_bytes() const = 0;

  // A layout that adapts to the values (multires) takes the deposits on other points than it keeps:
  // deposit() and normalise() work on deposit_points(), and adapt() turns every light sample's
  // values over them (blocks of deposit_points() x channels) into values over points().
  virtual size_t deposit_points() const { return points(); }
  virtual bool adaptive() const { return false; }
  virtual std::vector<float> adapt(const std::vector<float>& deposited, int channels) { return deposited; }
  // Sample points of each of `blocks` light samples' blocks: points() each, unless an adaptive
  // layout fits each light sample apart (multires, a tree per light sample).
  virtual std::vector<size_t> block_points(size_t blocks) const { return std::vector<size_t>(blocks, points()); }
  // What adapt() decided, for the build cache, and bytes of the table the values cannot be read
  // without (counted with each light sample's values, which it indexes).
  virtual std::vector<uint32_t> structure() const { return {}; }
  virtual void restore(std::vector<uint32_t> structure) { (void)structure; }
  virtual size_t index_bytes() const { return 0; }

 protected:
  VolumeLayout(Vec3 center, float radius) : center_(center), radius_(radius) {}
  Vec3 center_;
  float radius_;
};

// The cosine the paper orientation weights a track with: travel direction against the normal that
// faces the centre from `sample_direction` (unit, from the centre to the sample point). Light that
// travels towards the object does not reach a surface facing it.
inline float paper_cosine(const Vec3& travel, const Vec3& sample_direction) {
  return std::max(0.0f, glm::dot(travel, sample_direction));
}

// Adds `length` of `segment` into the values of one point, with the orientation's weighting.
inline void add_track(const PathSegment& segment, float length, const Vec3& sample_direction, Orientation orientation,
                      float* values) {
  if (orientation == Orientation::paper) {
    const float weight = length * paper_cosine(segment.direction, sample_direction);
    values[0] += weight * segment.power.r;
    values[1] += weight * segment.power.g;
    values[2] += weight * segment.power.b;
  } else {
    // Vector irradiance points where the light comes from: against the travel direction.
    const Vec3 towards_light = -segment.direction * length;
    for (int channel = 0; channel < 3; ++channel) {
      values[3 * channel + 0] += segment.power[channel] * towards_light.x;
      values[3 * channel + 1] += segment.power[channel] * towards_light.y;
      values[3 * channel + 2] += segment.power[channel] * towards_light.z;
    }
  }
}

// The piece [t_enter, t_exit] of a segment inside the ball (centre, radius); false when none.
bool clip_to_ball(const PathSegment& segment, const Vec3& center, float radius, float& t_enter, float& t_exit);

}  // namespace causticbench
