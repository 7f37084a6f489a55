// csl's CPU backend (backend: cpu): every receiver point sums the frame's spot lights, evaluated in
// closed form (evaluate_spot_light, spot_light_evaluate.h).
//
// The image is cut into squares of 8 x 8 pixels and each square's receivers into groups of up to 8.
// With `cull: on` (the default) a spot light is evaluated only for the groups it may light: a square's
// spot lights are those whose swept volume (SpotReach, spot_reach.h) meets the sphere around the
// square's points, and of those a group's are the ones that meet the group's sphere. The bound is
// conservative (a culled pair's evaluation is exactly zero), and every pixel still adds its spot lights
// in the same order, so the image is the same bit for bit as with `cull: off` (tested).
// With `lanes: vector` (the default) a group's points go through the light's geometry four at a time in
// double, with `lanes: float` eight at a time in float (evaluation_lanes.h), and only the rays that reach them are looked up: eight at a time from a stored
// one-channel image (tile_lookup.h), otherwise one by one; `lanes: scalar` evaluates each point alone.
// Shadow rays (occlusion: shadow_rays) always take the scalar path.
#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "core/parallel.h"
#include "methods/csl/csl.h"
#include "methods/csl/evaluation_lanes.h"
#include "methods/csl/spot_reach.h"
#include "methods/csl/tile_lookup.h"

namespace causticbench {

using namespace csl;

namespace {

constexpr int kSquare = 8;        // pixels a side of the squares whose spot lights are culled together
constexpr int kBlockSquares = 4;  // squares a side of the blocks the threads take (32 x 32 pixels)

// One spot light of the frame as the CPU backend evaluates it: a set's or an interpolated one.
struct FrameSpot {
  const SpotLight* stored = nullptr;
  const InterpolatedSpotLight* interpolated = nullptr;
  Color irradiance{0.0f};
  int channels = 1;
  SpotReach reach;
  LightLanes lanes;
  bool gathered = false;  // a stored image tile_lookups reads (tile_lookup.h)
};

// A group's points as the evaluation reads them (build space, as the scalar loop computed them).
struct Group {
  size_t count = 0;
  size_t pixel[kTilePoints];
  Vec3 point[kTilePoints], normal[kTilePoints], world_point[kTilePoints], world_normal[kTilePoints];
  float footprint[kTilePoints];
  PointTile tile;
  glm::dvec3 center{0.0};
  double radius = 0.0, near_axis = 0.0;
};

// The sphere around `count` points: their bounding box's centre and the farthest point from it.
void bound(const Vec3* points, size_t count, glm::dvec3& center, double& radius) {
  glm::dvec3 low(points[0]), high(points[0]);
  for (size_t i = 1; i < count; ++i) {
    low = glm::min(low, glm::dvec3(points[i]));
    high = glm::max(high, glm::dvec3(points[i]));
  }
  center = 0.5 * (low + high);
  radius = 0.0;
  for (size_t i = 0; i < count; ++i) radius = std::max(radius, glm::length(glm::dvec3(points[i]) - center));
  radius *= 1.0 + 1e-12;
}

// How one object's spot lights are evaluated at a group's points: the vector lanes (`vector`), or one
// point at a time, with shadow rays through `shadow_tracer` where it is set (occlusion: shadow_rays).
struct GroupEvaluation {
  const EvaluationSettings& settings;
  bool vector = true;
  LanePrecision precision = LanePrecision::double_precision;  // of the vector lanes' geometry
  const Tracer* shadow_tracer = nullptr;
  glm::mat3 to_world{1.0f};  // the object's build-space vectors to world ones, and its map's offset
  Vec3 offset{0.0f};
  int object = -1;

  // Adds to total[j] what `spot` sends to point j of `group` (`rays`: the lanes' scratch space).
  void add(const FrameSpot& spot, const Group& group, TileRays& rays, Color* total) const {
    if (vector) tile_rays(spot.lanes, group.tile, rays, precision);
    if (vector && spot.gathered) {
      // A stored one-channel image: the rays' lookups eight at a time, then the near-axis points alone.
      float value[kTilePoints] = {};
      tile_lookups(spot.stored->image, rays, group.count, value);
      for (size_t j = 0; j < group.count; ++j) {
        if ((rays.near_axis >> j) & 1u) {
          spot.stored->evaluate(group.point[j], group.normal[j], group.footprint[j], settings, &value[j]);
        }
        total[j] += Color(value[j]) * spot.irradiance;
      }
      return;
    }
    for (size_t j = 0; j < group.count; ++j) {
      float value[3] = {0.0f, 0.0f, 0.0f};
      if (vector) {
        const Vec3& point = group.point[j];
        const Vec3& normal = group.normal[j];
        if (spot.stored) {
          tile_value(*spot.stored, StoredImage(spot.stored->image), rays, j, point, normal, group.footprint[j],
                     settings, value);
        } else {
          tile_value(*spot.interpolated, spot.interpolated->image, rays, j, point, normal, group.footprint[j],
                     settings, value);
        }
      } else {
        // occlusion: shadow_rays: a ray's light reaches the point unless the path back towards
        // its light plane point meets another object before the caustic object itself (or the plane).
        const Vec3 world_point = group.world_point[j], world_normal = group.world_normal[j];
        auto visible = [&](const glm::dvec3& travel, const glm::dvec3& from) {
          const Vec3 from_world = to_world * (Vec3(from) - offset);
          const Vec3 towards = glm::normalize(-(to_world * Vec3(travel)));
          const float side = glm::dot(world_normal, towards) >= 0.0f ? 1.0f : -1.0f;
          Ray ray;
          ray.origin = world_point + (side * shadow_tracer->epsilon()) * world_normal;
          ray.direction = towards;
          ray.t_max = glm::length(from_world - ray.origin);
          SurfaceHit hit;
          return !shadow_tracer->intersect(ray, hit) || hit.object == object;
        };
        auto evaluate = [&](const auto& light) {
          if (shadow_tracer != nullptr) {
            light.evaluate(group.point[j], group.normal[j], group.footprint[j], settings, value, visible);
          } else {
            light.evaluate(group.point[j], group.normal[j], group.footprint[j], settings, value);
          }
        };
        spot.stored ? evaluate(*spot.stored) : evaluate(*spot.interpolated);
      }
      const Color added = spot.channels == 1 ? Color(value[0]) : Color(value[0], value[1], value[2]);
      total[j] += added * spot.irradiance;
    }
  }
};

}  // namespace

Image CslMethod::render(const GBuffer& gbuffer, const ParamSet& render) {
  if (render.text("backend") == "vulkan") return render_vulkan(gbuffer, render);
  note_cpu_render();
  Image result(gbuffer.width, gbuffer.height, 3);
  // occlusion, cull and lanes apply on the CPU backend only (the Vulkan kernel has no ray tracer).
  const bool shadow_rays = render.has("occlusion") && render.text("occlusion") == "shadow_rays";
  const bool cull = !render.has("cull") || render.text("cull") == "on";
  const std::string lanes = render.has("lanes") ? render.text("lanes") : "vector";
  const bool vector = !shadow_rays && lanes != "scalar";
  const LanePrecision precision = lanes == "float" ? LanePrecision::single_precision : LanePrecision::double_precision;
  // Per object: its evaluation settings (axis_epsilon is in its bounding radii) and the frame's spot
  // lights in the order every pixel adds them.
  std::vector<EvaluationSettings> settings_of;
  std::vector<std::vector<FrameSpot>> spots_of(objects_.size());
  for (size_t i = 0; i < objects_.size(); ++i) {
    settings_of.push_back(evaluation_settings(render, objects_[i].bounds));
    const bool correction = settings_of.back().intensity_correction;
    for (const LightView& light : frame_[i].lights) {
      auto add = [&](const SpotLight* stored, const InterpolatedSpotLight* interpolated, const SpotGeometry& geometry,
                     const auto& image) {
        FrameSpot spot;
        spot.stored = stored;
        spot.interpolated = interpolated;
        spot.irradiance = light.irradiance;
        spot.channels = image.channels();
        spot.reach = SpotReach(geometry, image.support_radius());
        spot.lanes = light_lanes(geometry, image.max_radius(), correction);
        spot.gathered = stored != nullptr && tile_lookups_apply(stored->image);
        spots_of[i].push_back(spot);
      };
      if (light.set != nullptr) {
        for (const SpotLight& spot : light.set->lights) add(&spot, nullptr, spot, spot.image);
      }
      for (const InterpolatedSpotLight& spot : light.interpolated) add(nullptr, &spot, spot.geometry, spot.image);
    }
  }
  const int squares_x = (gbuffer.width + kSquare - 1) / kSquare, squares_y = (gbuffer.height + kSquare - 1) / kSquare;
  const int blocks_x = (squares_x + kBlockSquares - 1) / kBlockSquares;
  const int blocks_y = (squares_y + kBlockSquares - 1) / kBlockSquares;
  std::vector<double> evaluations(static_cast<size_t>(blocks_x) * blocks_y, 0.0);
  parallel_blocks(evaluations.size(), 1, [&](size_t block, size_t, size_t) {
    double count = 0.0;
    std::vector<size_t> square_pixels;
    std::vector<uint32_t> square_spots;
    std::vector<Group> groups;
    std::vector<Vec3> square_points;
    TileRays rays;
    const int block_x = static_cast<int>(block) % blocks_x, block_y = static_cast<int>(block) / blocks_x;
    for (int sy = block_y * kBlockSquares; sy < std::min(squares_y, (block_y + 1) * kBlockSquares); ++sy) {
      for (int sx = block_x * kBlockSquares; sx < std::min(squares_x, (block_x + 1) * kBlockSquares); ++sx) {
        square_pixels.clear();
        for (int y = sy * kSquare; y < std::min(gbuffer.height, (sy + 1) * kSquare); ++y) {
          for (int x = sx * kSquare; x < std::min(gbuffer.width, (sx + 1) * kSquare); ++x) {
            const size_t pixel = static_cast<size_t>(y) * gbuffer.width + x;
            if (gbuffer.receiver[pixel]) square_pixels.push_back(pixel);
          }
        }
        if (square_pixels.empty()) continue;
        for (size_t i = 0; i < objects_.size(); ++i) {
          const ObjectFrame& view = frame_[i];
          const std::vector<FrameSpot>& spots = spots_of[i];
          if (spots.empty()) continue;
          const EvaluationSettings& settings = settings_of[i];
          const GroupEvaluation evaluation{settings, vector, precision, shadow_rays ? tracer_ : nullptr, view.to_world,
                                           view.map.offset, objects_[i].object};
          // The square's points in the object's build space, in groups of up to eight.
          groups.assign((square_pixels.size() + kTilePoints - 1) / kTilePoints, Group{});
          square_points.clear();
          double square_near = settings.on_axis == OnAxis::epsilon ? settings.axis_epsilon : 0.0;
          for (size_t k = 0; k < square_pixels.size(); ++k) {
            Group& group = groups[k / kTilePoints];
            const size_t pixel = square_pixels[k], j = group.count++;
            group.pixel[j] = pixel;
            group.world_point[j] = gbuffer.position[pixel];
            group.world_normal[j] = gbuffer.normal[pixel];
            group.point[j] = view.map.point(gbuffer.position[pixel]);
            group.normal[j] = glm::normalize(view.map.normals * gbuffer.normal[pixel]);
            // The disk of the pixel's footprint: the same area as its square.
            group.footprint[j] = gbuffer.footprint[pixel] * view.length_scale / std::sqrt(kPi);
            square_points.push_back(group.point[j]);
          }
          for (Group& group : groups) {
            bound(group.point, group.count, group.center, group.radius);
            group.tile = make_tile(group.point, group.normal, group.footprint, group.count, settings);
            for (size_t j = 0; j < group.count; ++j) group.near_axis = std::max(group.near_axis, group.tile.near_axis[j]);
            square_near = std::max(square_near, group.near_axis);
          }
          glm::dvec3 square_center;
          double square_radius;
          bound(square_points.data(), square_points.size(), square_center, square_radius);
          square_spots.clear();
          for (uint32_t s = 0; s < spots.size(); ++s) {
            if (!cull || spots[s].reach.may_reach(square_center, square_radius, square_near)) square_spots.push_back(s);
          }
          for (const Group& group : groups) {
            Color total[kTilePoints];
            std::fill(total, total + kTilePoints, Color(0.0f));
            for (uint32_t s : square_spots) {
              const FrameSpot& spot = spots[s];
              if (cull && !spot.reach.may_reach(group.center, group.radius, group.near_axis)) continue;
              count += static_cast<double>(group.count);
              evaluation.add(spot, group, rays, total);
            }
            for (size_t j = 0; j < group.count; ++j) {
              const size_t pixel = group.pixel[j];
              const Color before(result.at(pixel, 0), result.at(pixel, 1), result.at(pixel, 2));
              result.set_rgb(pixel, before + total[j]);
            }
          }
        }
      }
    }
    evaluations[block] = count;
  });
  evaluations_ = 0.0;
  for (double count : evaluations) evaluations_ += count;
  return result;
}

}  // namespace causticbench
