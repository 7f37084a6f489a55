#version 450
// Variable splats, first pass (Wyman & Dachsbacher's coarse density buffer): each landed photon drawn as
// one point into the cell of 4 x 4 caustic-map texels that holds it; blending adds 1 per photon.
layout(std430, binding = 0) readonly buffer Landings { vec4 landings[]; };

layout(push_constant) uniform Parameters {
  uint first_photon;
  uint cells;
} parameters;

void main() {
  const vec4 landing = landings[parameters.first_photon + uint(gl_VertexIndex)];
  gl_PointSize = 1.0;
  if (landing.z != 0.0) {  // not landed: outside the clip volume, drawn nowhere
    gl_Position = vec4(-2.0, -2.0, 0.0, 1.0);
    return;
  }
  const int last = int(parameters.cells) - 1;
  const vec2 cell = vec2(min(int(landing.x) / 4, last), min(int(landing.y) / 4, last)) + 0.5;
  gl_Position = vec4(cell / float(parameters.cells) * 2.0 - 1.0, 0.0, 1.0);
}
