#version 450
// caustic_volume's footprints: per volume the convex hull of its six corners projected into the image
// (pushed a pixel outwards, so that rounding keeps no receiver point of the volume out), as a triangle
// fan the CPU made (methods/caustic_volume/frame_data.h); the whole image where a corner lies behind the
// camera. The rasteriser covers each pixel of a footprint once; the fragment stage tests the pixel's
// receiver point against the volume exactly.
layout(std430, binding = 0) readonly buffer Footprints { vec4 footprints[]; };

layout(push_constant) uniform Parameters {
  uint width;
  uint height;
  uint intensity;  // 0 interpolated, 1 constant
} parameters;

layout(location = 0) flat out uint volume;

void main() {
  const vec4 corner = footprints[gl_VertexIndex];  // x, y in pixels (y down the rows), volume, 0
  volume = uint(corner.z);
  gl_Position = vec4(corner.x / float(parameters.width) * 2.0 - 1.0, corner.y / float(parameters.height) * 2.0 - 1.0,
                     0.0, 1.0);
}
