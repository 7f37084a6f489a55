#version 450
// csl (Liu et al. 2008) on Vulkan: one invocation per receiver pixel sums the light of every spot light
// of every specular object (Sections 2.2 to 2.4). The steps and their order are those of the CPU
// evaluation (methods/csl/spot_light_evaluate.h, spot_light.cpp, interpolation.cpp) in float where
// the CPU solves in double: into the light's frame, the up to three radii of Eqs. 2 and 3 in product
// form, radii beyond the image dropped, Eq. 4's area ratio, the bilinear image lookup with its uint16
// decoding, the blend of an interpolated light's source images, and both on-axis treatments. Record
// layouts: methods/csl/frame_data.h.
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer ReceiverPositions { vec4 receiver_position[]; };
layout(std430, binding = 1) readonly buffer ReceiverNormals { vec4 receiver_normal[]; };
layout(std430, binding = 2) readonly buffer Objects { vec4 object_data[]; };
layout(std430, binding = 3) readonly buffer ObjectLights { uint object_lights[]; };
layout(std430, binding = 4) readonly buffer Lights { vec4 light_data[]; };
layout(std430, binding = 5) readonly buffer LightImages { uint light_images[]; };
layout(std430, binding = 6) readonly buffer Images { uint image_layout[]; };
layout(std430, binding = 7) readonly buffer ImageScalars { vec4 image_scalar[]; };
layout(std430, binding = 8) readonly buffer Texels { uint texel_word[]; };
layout(std430, binding = 9) readonly buffer Radial { float radial[]; };
layout(std430, binding = 10) writeonly buffer Irradiance { vec4 irradiance[]; };

layout(push_constant) uniform Parameters {
  uint pixel_count;
  uint object_count;
  uint intensity_correction;
  uint on_axis;  // 0 integrate, 1 epsilon
} p;

const float kPi = 3.14159265358979;
const uint kObjectVectors = 7u, kLightVectors = 9u, kLightWords = 4u, kImageWords = 6u;

// ---- Intensity images (IntensityImage in spot_light.cpp) ----

float texel(uint image, int i, int j, int c) {
  uint base = kImageWords * image;
  uint size = image_layout[base + 1u], channels = image_layout[base + 2u];
  uint element = (uint(j) * size + uint(i)) * channels + uint(c);
  if (image_layout[base + 3u] == 0u) return uintBitsToFloat(texel_word[image_layout[base] + element]);
  uint word = texel_word[image_layout[base] + (element >> 1)];
  uint q = (element & 1u) == 0u ? (word & 0xffffu) : (word >> 16);
  return float(q) * image_scalar[image][1 + c];
}

// Bilinear, zero beyond the edge texels (IntensityImage::lookup).
vec3 image_lookup(uint image, float x, float y) {
  vec3 value = vec3(0.0);
  int size = int(image_layout[kImageWords * image + 1u]);
  int channels = int(image_layout[kImageWords * image + 2u]);
  float half_size = image_scalar[image].x;
  float scale = float(size) / (2.0 * half_size);
  float fx = (x + half_size) * scale - 0.5, fy = (y + half_size) * scale - 0.5;
  if (!(fx > -1.0 && fy > -1.0 && fx < float(size) && fy < float(size))) return value;
  int i0 = int(floor(fx)), j0 = int(floor(fy));
  float tx = fx - float(i0), ty = fy - float(j0);
  float weights[4] = float[4]((1.0 - tx) * (1.0 - ty), tx * (1.0 - ty), (1.0 - tx) * ty, tx * ty);
  for (int k = 0; k < 4; ++k) {
    int i = i0 + (k & 1), j = j0 + (k >> 1);
    if (i < 0 || j < 0 || i >= size || j >= size) continue;
    for (int c = 0; c < channels; ++c) value[c] += weights[k] * texel(image, i, j, c);
  }
  return value;
}

// The flux of the rays leaving radii [0, r] from the image's radial tables (IntensityImage::flux_within).
vec3 image_flux_within(uint image, float r) {
  uint base = kImageWords * image;
  uint channels = image_layout[base + 2u], offset = image_layout[base + 4u];
  int bins = int(image_layout[base + 5u]);
  uint ring = offset + uint(bins + 1) * channels;
  float bin_width = image_scalar[image].x * 1.41421356237 / float(bins);
  float position = clamp(r / bin_width, 0.0, float(bins));
  int k = min(bins - 1, int(position));
  float t = (position - float(k)) * bin_width;
  vec3 flux = vec3(0.0);
  for (uint c = 0u; c < channels; ++c) {
    uint here = uint(k) * channels + c, next = here + channels;
    flux[c] = radial[offset + here] + radial[ring + here] * t + 0.5 * (radial[ring + next] - radial[ring + here]) * t * t / bin_width;
  }
  return flux;
}

// ---- A spot light's image: one stored image (weight 1, identity map) or the blend of up to three
// (BlendedImage in interpolation.cpp) ----

bool light_lookup(uint light, int channels, float x, float y, out vec3 value) {
  value = vec3(0.0);
  bool inside = false;
  uint sources = light_images[kLightWords * light];
  vec4 weights = light_data[kLightVectors * light + 5u];
  for (uint s = 0u; s < sources; ++s) {
    uint image = light_images[kLightWords * light + 1u + s];
    vec4 map = light_data[kLightVectors * light + 6u + s];
    float sx = map.x * x + map.y * y, sy = map.z * x + map.w * y;
    float half_size = image_scalar[image].x;
    if (abs(sx) > half_size || abs(sy) > half_size) continue;
    inside = true;
    vec3 read = image_lookup(image, sx, sy);
    // A one-channel image under a coloured blend: the same value in every channel.
    value += weights[s] * (int(image_layout[kImageWords * image + 2u]) == channels ? read : vec3(read.x));
  }
  return inside;
}

vec3 light_flux_within(uint light, int channels, float r) {
  vec3 flux = vec3(0.0);
  uint sources = light_images[kLightWords * light];
  vec4 weights = light_data[kLightVectors * light + 5u];
  for (uint s = 0u; s < sources; ++s) {
    uint image = light_images[kLightWords * light + 1u + s];
    vec3 read = image_flux_within(image, r);
    flux += weights[s] * (int(image_layout[kImageWords * image + 2u]) == channels ? read : vec3(read.x));
  }
  return flux;
}

// ---- The profile (Profile in spot_light.h) ----

struct Radii {
  int count;
  float radius[3];
  int side[3];
};

void keep(inout Radii radii, float r, float max_radius, int side) {
  if (!(r > 0.0 && r <= max_radius)) return;
  for (int i = 0; i < radii.count; ++i) {
    if (radii.side[i] == side && radii.radius[i] == r) return;  // a double root, once
  }
  if (radii.count < 3) {
    radii.radius[radii.count] = r;
    radii.side[radii.count] = side;
    ++radii.count;
  }
}

// Positive roots of a r^2 + b r + c = 0 up to max_radius in the product form that loses no digits
// when a is tiny or b^2 >> ac.
void positive_roots(float a, float b, float c, float max_radius, int side, inout Radii radii) {
  if (a == 0.0) {
    if (b != 0.0) keep(radii, -c / b, max_radius, side);
    return;
  }
  float discriminant = b * b - 4.0 * a * c;
  if (discriminant < 0.0) return;
  float q = -0.5 * (b + (b < 0.0 ? -sqrt(discriminant) : sqrt(discriminant)));
  if (q == 0.0) return;
  keep(radii, q / a, max_radius, side);
  keep(radii, c / q, max_radius, side);
}

// Eqs. 2 and 3: s(r) = -A r^2 - B r = +rho (case i) and -rho (case ii).
Radii solve_radii(float kappa, float beta, float z, float rho, float max_radius) {
  Radii radii;
  radii.count = 0;
  float a = z * kappa * beta, b = z * kappa - 1.0;
  positive_roots(a, b, rho, max_radius, 1, radii);
  positive_roots(a, b, -rho, max_radius, -1, radii);
  return radii;
}

// ---- One spot light at one point (evaluate_spot_light) ----

vec3 evaluate(uint light, vec3 point, vec3 normal, float footprint_radius, float axis_epsilon) {
  vec4 d0 = light_data[kLightVectors * light], d1 = light_data[kLightVectors * light + 1u];
  vec4 d2 = light_data[kLightVectors * light + 2u], d3 = light_data[kLightVectors * light + 3u];
  vec3 origin = d0.xyz, a = d1.xyz, u = d2.xyz, v = d3.xyz;
  float kappa = d0.w, beta = d1.w, max_radius = d2.w;
  int channels = int(d3.w);
  if (light_images[kLightWords * light] == 0u) return vec3(0.0);  // a black spot light
  vec3 offset = point - origin;
  float z = dot(offset, a);
  if (!(z > 0.0)) return vec3(0.0);  // the rays start at the light plane
  vec3 across = offset - z * a;
  float rho = length(across);
  vec3 total = vec3(0.0);
  if (p.on_axis == 1u && rho < axis_epsilon) {
    // The paper's treatment: move the point out to epsilon from the axis.
    across = rho > 0.0 ? across * (axis_epsilon / rho) : axis_epsilon * u;
    rho = axis_epsilon;
  } else if (p.on_axis == 0u && rho < footprint_radius) {
    // The footprint's disk centred on the axis gathers the flux of every ray whose signed radius at
    // this height is within it; its flux over its area.
    float disk = footprint_radius;
    Radii edges = solve_radii(kappa, beta, z, disk, max_radius);
    float breaks[5] = float[5](0.0, max_radius, 0.0, 0.0, 0.0);
    int count = 2;
    for (int i = 0; i < edges.count; ++i) breaks[count++] = edges.radius[i];
    for (int i = 1; i < count; ++i) {  // insertion sort
      float value = breaks[i];
      int j = i - 1;
      while (j >= 0 && breaks[j] > value) {
        breaks[j + 1] = breaks[j];
        --j;
      }
      breaks[j + 1] = value;
    }
    vec3 flux = vec3(0.0);
    for (int i = 0; i + 1 < count; ++i) {
      float middle = 0.5 * (breaks[i] + breaks[i + 1]);
      float s = middle * (1.0 - z * kappa * (1.0 + beta * middle));
      if (!(breaks[i + 1] > breaks[i]) || abs(s) >= disk) continue;
      flux += light_flux_within(light, channels, breaks[i + 1]) - light_flux_within(light, channels, breaks[i]);
    }
    float cosine = max(0.0, -dot(normal, a));
    float area = kPi * disk * disk;
    total = flux / area * cosine;
    return channels == 1 ? vec3(total.x) : total;
  }
  if (!(rho > 0.0)) return vec3(0.0);
  vec3 outward = across / rho;
  Radii radii = solve_radii(kappa, beta, z, rho, max_radius);
  for (int i = 0; i < radii.count; ++i) {
    float r = radii.radius[i];
    vec3 from = (float(radii.side[i]) * r) * outward;  // p - c
    vec3 value;
    if (!light_lookup(light, channels, dot(from, u), dot(from, v), value)) continue;  // beyond the image
    float g = kappa * (1.0 + beta * r);
    // Eq. 4, bounded so that a point exactly on the envelope where two radii merge stays finite.
    float area_ratio = abs((1.0 - z * g) * (1.0 - z * kappa - 2.0 * z * kappa * beta * r));
    float correction = p.intensity_correction == 1u ? 1.0 / max(1e-6, area_ratio) : 1.0;
    vec3 direction = normalize(a - g * from);
    // The image holds flux per unit light-plane area; a receiver facing n takes |n.e| / |a.e| of it.
    float cosine = max(0.0, -dot(normal, direction)) / dot(a, direction);
    if (cosine <= 0.0) continue;
    total += value * correction * cosine;
  }
  return channels == 1 ? vec3(total.x) : total;
}

void main() {
  uint pixel = gl_GlobalInvocationID.x;
  if (pixel >= p.pixel_count) return;
  vec4 position = receiver_position[pixel];
  vec3 result = vec3(0.0);
  if (position.w != 0.0) {
    vec4 normal_footprint = receiver_normal[pixel];
    for (uint object = 0u; object < p.object_count; ++object) {
      uint first = object_lights[2u * object], count = object_lights[2u * object + 1u];
      if (count == 0u) continue;
      uint o = kObjectVectors * object;
      mat3 linear = mat3(object_data[o].xyz, object_data[o + 1u].xyz, object_data[o + 2u].xyz);
      mat3 normals = mat3(object_data[o + 4u].xyz, object_data[o + 5u].xyz, object_data[o + 6u].xyz);
      vec3 point = linear * position.xyz + object_data[o + 3u].xyz;
      vec3 normal = normalize(normals * normal_footprint.xyz);
      // The disk of the pixel's footprint: the same area as its square.
      float footprint = normal_footprint.w * object_data[o + 3u].w / sqrt(kPi);
      float axis_epsilon = object_data[o + 4u].w;
      vec3 total = vec3(0.0);
      for (uint light = first; light < first + count; ++light) {
        total += evaluate(light, point, normal, footprint, axis_epsilon) * light_data[kLightVectors * light + 4u].xyz;
      }
      result += total;
    }
  }
  irradiance[pixel] = vec4(result, 0.0);
}
