// Building the caustic volumes of one specular object under one light: its triangles, the vertex rays
// they send out, and both intensity modes' quantities.
#include <algorithm>
#include <cmath>
#include <limits>

#include "core/optics.h"
#include "core/parallel.h"
#include "core/scene.h"
#include "methods/caustic_volume/volume.h"

namespace causticbench::caustic_volume {

void BeamStatistics::add(const BeamStatistics& other) {
  triangles += other.triangles;
  lit += other.lit;
  unlit += other.unlit;
  dropped += other.dropped;
  torn += other.torn;
  flux_lit += other.flux_lit;
  flux_dropped += other.flux_dropped;
  flux_torn += other.flux_torn;
}

namespace {

// Where and how light leaves one vertex of a lit triangle.
struct VertexRay {
  glm::dvec3 light{0.0};       // the direction light travels there (unit)
  Color strength{0.0f};        // irradiance across the light there, W/m^2
  glm::dvec3 origin{0.0};      // where it leaves: the vertex, or where it leaves the solid
  glm::dvec3 direction{0.0};   // outgoing, unit
  Color factor{0.0f};          // reflectance or Fresnel transmittance (and absorption inside a solid)
  bool leaves = false;
  bool in_medium = false;      // refracted once: the receivers lie in the medium (its absorption applies)
  int bounces = -1;            // through a solid: total internal reflections before it left
};

// A refracted vertex ray through a solid glass object to where it leaves, total internal reflections
// followed up to kMaxInternal: whether it meets its object again at all (auto's test for a solid), and
// whether it left.
constexpr int kMaxInternal = 4;
enum class Through { not_a_solid, left, trapped };

Through leave_solid(const Tracer& tracer, int object, const glm::dvec3& entry, const glm::dvec3& inward,
                    const glm::dvec3& direction, const Material& material, VertexRay& ray) {
  Ray current{Vec3(entry + inward * double(tracer.epsilon())), Vec3(direction)};
  double inside = 0.0;
  for (int bounce = 0; bounce <= kMaxInternal; ++bounce) {
    SurfaceHit hit;
    if (!tracer.intersect(current, hit) || hit.object != object)
      return bounce == 0 ? Through::not_a_solid : Through::trapped;  // another object inside: not followed
    inside += glm::length(glm::dvec3(hit.position) - glm::dvec3(current.origin));
    const Vec3 d = current.direction, outward = hit.shading_normal;
    const Vec3 facing = glm::dot(d, outward) < 0.0f ? outward : -outward;  // against the ray
    const float cos_inside = std::max(0.0f, -glm::dot(d, facing));
    const float eta = glm::dot(d, outward) > 0.0f ? 1.0f / material.ior : material.ior;
    Vec3 out;
    if (refract(d, facing, eta, out)) {
      ray.origin = glm::dvec3(hit.position);
      ray.direction = glm::normalize(glm::dvec3(out));
      ray.factor *= (1.0f - fresnel_dielectric(cos_inside, eta)) * glm::exp(-material.absorption * static_cast<float>(inside));
      ray.bounces = bounce;
      return Through::left;
    }
    current = tracer.spawn(hit, reflect(d, facing));  // total internal reflection
  }
  return Through::trapped;
}

// Whether light from `light` arrives at `point` along a direction: a point light at the point itself (placed
// on a tessellated vertex, or on a ring's rim) has none there, and the point is taken as unlit (its
// triangles' light is counted as dropped). Within the tracer's offset the direction would be noise.
bool light_has_direction(const LightFrame& light, const glm::dvec3& point, double epsilon) {
  if (light.kind == LightKind::directional) return true;
  const glm::dvec3 d = point - glm::dvec3(light.position);
  return glm::dot(d, d) > epsilon * epsilon;
}

glm::dvec3 light_travel(const LightFrame& light, const glm::dvec3& point) {
  if (light.kind == LightKind::directional) return -glm::dvec3(light.direction_to_light);
  return glm::normalize(point - glm::dvec3(light.position));
}

Color light_strength(const LightFrame& light, const glm::dvec3& point) {
  if (light.kind == LightKind::directional) return light.light->irradiance;
  const glm::dvec3 d = point - glm::dvec3(light.position);
  return light.light->intensity * static_cast<float>(1.0 / std::max(glm::dot(d, d), 1e-30));
}

// The vertex ray at `point` with shading normal `normal` turned to the lit side `side` (+1: the side its
// normal faces).
VertexRay vertex_ray(const Tracer& tracer, int object, const LightFrame& light, const glm::dvec3& point,
                     const glm::dvec3& normal, double side, const Material& material, Refraction refraction) {
  VertexRay ray;
  if (!light_has_direction(light, point, tracer.epsilon())) return ray;  // leaves: false, no light
  ray.light = light_travel(light, point);
  ray.strength = light_strength(light, point);
  ray.origin = point;
  const glm::dvec3 facing = side * normal;  // towards the light
  const float cos_incident = static_cast<float>(std::max(0.0, -glm::dot(ray.light, facing)));
  const Vec3 travel(ray.light), n(facing);
  if (material.kind != MaterialKind::glass) {
    ray.factor = material.mirror_reflectance(cos_incident);
    ray.direction = glm::normalize(glm::dvec3(reflect(travel, n)));
    ray.leaves = true;
    return ray;
  }
  // Into the glass from the outside (the side its normal faces), or out of it.
  const float eta = side > 0.0 ? material.ior : 1.0f / material.ior;
  Vec3 transmitted;
  if (!refract(travel, n, eta, transmitted)) return ray;
  ray.factor = Color(1.0f - fresnel_dielectric(cos_incident, eta));
  ray.direction = glm::normalize(glm::dvec3(transmitted));
  if (refraction != Refraction::one_interface) {
    VertexRay through = ray;
    switch (leave_solid(tracer, object, point, -facing, ray.direction, material, through)) {
      case Through::left:
        through.leaves = true;
        return through;
      case Through::trapped: return ray;  // leaves: false
      case Through::not_a_solid:
        if (refraction == Refraction::through_object) return ray;  // nothing to go through: not modelled
        break;  // auto: a surface, the receivers lie in its medium
    }
  }
  ray.leaves = true;
  ray.in_medium = true;
  return ray;
}

}  // namespace

ReceiverBox receiver_box(const SceneFrame& frame) {
  ReceiverBox box;
  box.lower = glm::dvec3(std::numeric_limits<double>::infinity());
  box.upper = -box.lower;
  auto hold = [&](const glm::dvec3& point) {
    box.lower = glm::min(box.lower, point);
    box.upper = glm::max(box.upper, point);
    box.empty = false;
  };
  for (size_t object = 0; object < frame.scene->objects.size(); ++object) {
    const SceneObject& described = frame.scene->objects[object];
    if (!described.material.receives_caustics()) continue;
    if (described.shape.is_analytic()) {
      glm::dvec3 lower, upper;
      analytic_bounds(described.shape, lower, upper);
      for (int corner = 0; corner < 8; ++corner)
        hold(glm::dvec3(frame.transforms[object].point(Vec3(corner & 1 ? upper.x : lower.x, corner & 2 ? upper.y : lower.y,
                                                             corner & 4 ? upper.z : lower.z))));
    } else {
      for (const Vec3& point : frame.world_meshes[object].positions) hold(glm::dvec3(point));
    }
  }
  return box;
}

double box_cap(const ReceiverBox& box, const std::array<glm::dvec3, 3>& origin, const std::array<glm::dvec3, 3>& direction) {
  double cap = std::numeric_limits<double>::infinity();
  for (int axis = 0; axis < 3; ++axis) {
    const bool up = direction[0][axis] > 0.0, down = direction[0][axis] < 0.0;
    bool same = up || down;
    for (int i = 1; i < 3 && same; ++i) same = up ? direction[i][axis] > 0.0 : direction[i][axis] < 0.0;
    if (!same) continue;  // rays parallel to the slab, or travelling both ways: it bounds nothing
    const double plane = up ? box.upper[axis] : box.lower[axis];
    double slab = 0.0;
    for (int i = 0; i < 3; ++i) slab = std::max(slab, (plane - origin[i][axis]) / direction[i][axis]);
    cap = std::min(cap, slab);
  }
  return cap;
}

void build_volumes(const Tracer& tracer, const LightFrame& light, const SurfaceMesh& mesh, int object,
                   const Material& material, Refraction refraction, double t_max, const ReceiverBox* box,
                   std::vector<Volume>& volumes, BeamStatistics& statistics) {
  const size_t triangle_count = mesh.triangles.size();
  statistics.triangles += triangle_count;
  // Per triangle, the side the light arrives on (+1: the side its winding faces, which the mesh's normals
  // agree with; 0: edge-on), from its centroid's facing.
  std::vector<double> facing_side(triangle_count, 0.0);
  for (size_t index = 0; index < triangle_count; ++index) {
    const glm::uvec3& triangle = mesh.triangles[index];
    const glm::dvec3 p0 = mesh.positions[triangle.x], p1 = mesh.positions[triangle.y], p2 = mesh.positions[triangle.z];
    const glm::dvec3 centroid = (p0 + p1 + p2) / 3.0;
    if (!light_has_direction(light, centroid, tracer.epsilon())) continue;  // the light on its face: edge-on
    const double facing = glm::dot(glm::cross(p1 - p0, p2 - p0), light_travel(light, centroid));
    facing_side[index] = facing < 0.0 ? 1.0 : facing > 0.0 ? -1.0 : 0.0;
  }
  // The side of its normal a corner of triangle `index` is lit on (0: the side the normal faces, 1 the
  // other), and the triangle's winding.
  auto corner_side = [&](size_t index, uint32_t vertex) {
    const glm::uvec3& triangle = mesh.triangles[index];
    const glm::dvec3 p0 = mesh.positions[triangle.x];
    const glm::dvec3 winding = glm::cross(mesh.positions[triangle.y] - p0, mesh.positions[triangle.z] - p0);
    return glm::dot(mesh.normals[vertex], winding) * facing_side[index] > 0.0 ? 0 : 1;
  };
  // Which vertices see the light, on the sides some triangle facing the light needs (one shadow ray each):
  // the vertices lie on the exact surface, where a tessellated triangle's centroid lies inside a curved
  // one by up to its sagitta, more than the tracer's offset, and would be shadowed by its own shape.
  std::vector<uint8_t> sees[2], needed[2];
  for (int s = 0; s < 2; ++s) sees[s].assign(mesh.positions.size(), 0), needed[s].assign(mesh.positions.size(), 0);
  for (size_t index = 0; index < triangle_count; ++index) {
    if (facing_side[index] == 0.0) continue;
    for (int corner = 0; corner < 3; ++corner) {
      const uint32_t vertex = mesh.triangles[index][corner];
      if (glm::dot(mesh.normals[vertex], mesh.normals[vertex]) != 0.0) needed[corner_side(index, vertex)][vertex] = 1;
    }
  }
  parallel_blocks(mesh.positions.size(), 256, [&](size_t begin, size_t end, size_t) {
    for (size_t vertex = begin; vertex < end; ++vertex) {
      const glm::dvec3 point = mesh.positions[vertex];
      if (!light_has_direction(light, point, tracer.epsilon())) continue;  // the light sits on it: unlit
      const glm::dvec3 travel = light_travel(light, point);
      for (int s = 0; s < 2; ++s) {
        if (!needed[s][vertex]) continue;
        const glm::dvec3 start = point + (s == 0 ? 1.0 : -1.0) * mesh.normals[vertex] * double(tracer.epsilon());
        const float distance = light.kind == LightKind::directional
                                   ? 1e30f
                                   : static_cast<float>(glm::length(glm::dvec3(light.position) - start));
        sees[s][vertex] = !tracer.occluded(Vec3(start), Vec3(-travel), distance);
      }
    }
  });
  // Per triangle: lit or not. Lit: it faces the light and a vertex sees it; a vertex in shadow brings no
  // light (the interpolation makes a shadow's edge across a triangle a ramp, not a step).
  std::vector<double> side(triangle_count, 0.0);
  std::vector<std::array<uint8_t, 3>> vertex_lit(triangle_count, {0, 0, 0});
  parallel_blocks(triangle_count, 256, [&](size_t begin, size_t end, size_t) {
    for (size_t index = begin; index < end; ++index) {
      const double lit_side = facing_side[index];
      if (lit_side == 0.0) continue;
      const glm::uvec3& triangle = mesh.triangles[index];
      int seeing = 0;
      for (int corner = 0; corner < 3; ++corner) {
        const uint32_t vertex = triangle[corner];
        uint8_t lit = 0;
        if (glm::dot(mesh.normals[vertex], mesh.normals[vertex]) == 0.0) {
          // A flat mesh's vertex (its own copy per triangle), off the triangle along its winding.
          const glm::dvec3 p0 = mesh.positions[triangle.x];
          const glm::dvec3 winding = glm::cross(mesh.positions[triangle.y] - p0, mesh.positions[triangle.z] - p0);
          const glm::dvec3 start = mesh.positions[vertex] + lit_side * glm::normalize(winding) * double(tracer.epsilon());
          const float distance = light.kind == LightKind::directional
                                     ? 1e30f
                                     : static_cast<float>(glm::length(glm::dvec3(light.position) - start));
          lit = light_has_direction(light, start, tracer.epsilon()) &&
                !tracer.occluded(Vec3(start), Vec3(-light_travel(light, start)), distance);
        } else {
          lit = sees[corner_side(index, vertex)][vertex];
        }
        vertex_lit[index][corner] = lit;
        seeing += lit;
      }
      if (seeing > 0) side[index] = lit_side;
    }
  });
  // Per lit triangle and vertex its ray; a vertex shared by lit triangles of one side has one ray.
  std::vector<VertexRay> rays[2];
  std::vector<uint8_t> has_ray[2];
  for (int s = 0; s < 2; ++s) {
    rays[s].assign(mesh.positions.size(), VertexRay{});
    has_ray[s].assign(mesh.positions.size(), 0);
  }
  for (size_t index = 0; index < triangle_count; ++index) {
    if (side[index] == 0.0) continue;
    const int s = side[index] > 0.0 ? 0 : 1;
    const glm::uvec3& triangle = mesh.triangles[index];
    for (uint32_t vertex : {triangle.x, triangle.y, triangle.z}) {
      if (has_ray[s][vertex]) continue;
      glm::dvec3 normal = mesh.normals[vertex];
      if (glm::dot(normal, normal) == 0.0) {  // flat mesh: the triangle's own normal
        const glm::dvec3 p0 = mesh.positions[triangle.x];
        normal = glm::normalize(glm::cross(mesh.positions[triangle.y] - p0, mesh.positions[triangle.z] - p0));
      }
      rays[s][vertex] = vertex_ray(tracer, object, light, mesh.positions[vertex], normal, side[index], material, refraction);
      has_ray[s][vertex] = 1;
    }
  }
  // The one-rings: per vertex and side, the lit triangles' area across the light arriving at the vertex
  // and their cross-section across the vertex's outgoing direction as a quadratic in t.
  std::vector<double> ring_in[2];
  std::vector<std::array<double, 3>> ring_out[2];
  for (int s = 0; s < 2; ++s) {
    ring_in[s].assign(mesh.positions.size(), 0.0);
    ring_out[s].assign(mesh.positions.size(), {0.0, 0.0, 0.0});
  }
  const size_t first_volume = volumes.size();
  uint64_t unlit = 0;
  for (size_t index = 0; index < triangle_count; ++index) {
    if (side[index] == 0.0) {
      ++unlit;
      continue;
    }
    const int s = side[index] > 0.0 ? 0 : 1;
    const glm::uvec3& triangle = mesh.triangles[index];
    const uint32_t v[3] = {triangle.x, triangle.y, triangle.z};
    const VertexRay* r[3] = {&rays[s][v[0]], &rays[s][v[1]], &rays[s][v[2]]};
    const glm::dvec3 p0 = mesh.positions[v[0]];
    const glm::dvec3 centroid = (p0 + mesh.positions[v[1]] + mesh.positions[v[2]]) / 3.0;
    const glm::dvec3 a1 = mesh.positions[v[1]] - p0, a2 = mesh.positions[v[2]] - p0;
    const double area_in = 0.5 * std::abs(glm::dot(glm::cross(a1, a2), light_travel(light, centroid)));
    const float lit[3] = {float(vertex_lit[index][0]), float(vertex_lit[index][1]), float(vertex_lit[index][2])};
    const Color mean_strength = (r[0]->strength * lit[0] + r[1]->strength * lit[1] + r[2]->strength * lit[2]) * (1.0f / 3.0f);
    const double flux = luminance(mean_strength) * area_in;
    if (!r[0]->leaves || !r[1]->leaves || !r[2]->leaves) {
      ++statistics.dropped;
      statistics.flux_dropped += flux;
      side[index] = 0.0;
      continue;
    }
    // Through a solid the three rays must leave alike: the same number of internal reflections, all
    // through the solid or none. Otherwise the beam tore (across a total internal reflection's edge, or
    // between faces): dropped and counted.
    if (r[0]->bounces != r[1]->bounces || r[0]->bounces != r[2]->bounces || r[0]->in_medium != r[1]->in_medium ||
        r[0]->in_medium != r[2]->in_medium) {
      ++statistics.torn;
      statistics.flux_torn += flux;
      side[index] = 0.0;
      continue;
    }
    Volume volume;
    volume.object = object;
    volume.side = s == 0 ? 1 : -1;
    volume.self_gap = 0.5 * std::sqrt(std::max({glm::dot(a1, a1), glm::dot(a2, a2), glm::dot(a2 - a1, a2 - a1)}));
    volume.t_max = t_max;
    if (box) {
      const std::array<glm::dvec3, 3> origins = {r[0]->origin, r[1]->origin, r[2]->origin};
      const std::array<glm::dvec3, 3> directions = {r[0]->direction, r[1]->direction, r[2]->direction};
      volume.t_max = std::min(t_max, box_cap(*box, origins, directions));
    }
    volume.area_in = area_in;
    volume.flux_entering = flux;
    volume.flux = luminance((r[0]->factor * r[0]->strength * lit[0] + r[1]->factor * r[1]->strength * lit[1] +
                             r[2]->factor * r[2]->strength * lit[2]) *
                            (1.0f / 3.0f)) * area_in;
    glm::dvec3 mean(0.0);
    for (int i = 0; i < 3; ++i) {
      volume.origin[i] = r[i]->origin;
      volume.direction[i] = r[i]->direction;
      volume.arriving[i] = r[i]->strength * r[i]->factor * lit[i];
      mean += r[i]->direction;
    }
    volume.mean_direction = glm::normalize(mean);
    if (r[0]->in_medium) volume.absorption = material.absorption;
    finish_volume(volume);
    // This triangle's share of its vertices' one-rings.
    const glm::dvec3 winding = glm::cross(a1, a2);
    for (int i = 0; i < 3; ++i) {
      ring_in[s][v[i]] += 0.5 * glm::dot(winding, r[i]->light);
      for (int j = 0; j < 3; ++j) ring_out[s][v[i]][j] += 0.5 * glm::dot(volume.k[j], r[i]->direction);
    }
    ++statistics.lit;
    statistics.flux_lit += flux;
    volumes.push_back(volume);
  }
  statistics.unlit += unlit;
  // The one-ring sums, now complete, into each volume.
  size_t next = first_volume;
  for (size_t index = 0; index < triangle_count; ++index) {
    if (side[index] == 0.0) continue;
    const int s = side[index] > 0.0 ? 0 : 1;
    const glm::uvec3& triangle = mesh.triangles[index];
    const uint32_t v[3] = {triangle.x, triangle.y, triangle.z};
    Volume& volume = volumes[next++];
    for (int i = 0; i < 3; ++i) {
      volume.ring_area_in[i] = std::abs(ring_in[s][v[i]]);
      volume.ring_area_out[i] = ring_out[s][v[i]];
    }
  }
}

}  // namespace causticbench::caustic_volume
