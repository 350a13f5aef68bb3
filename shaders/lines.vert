#version 330 core
// World-space line vertices. Each is pulled toward the eye by a small fraction of its
// distance: that keeps its place on screen exactly (it moves along its own sight line) and
// lets lines lying on a surface win the depth test against that surface, at any scale.
// Opacity falls with distance along the view axis, from fade_start to fade_end, to
// far_alpha of the vertex's own: far lines recede behind near ones (far_alpha 1: no fading).
layout(location = 0) in vec3 position;
layout(location = 1) in vec4 vertex_colour;
uniform mat4 view;
uniform mat4 projection;
uniform float depth_bias;
uniform float fade_start;
uniform float fade_end;
uniform float far_alpha;
out vec4 line_colour;

void main() {
  vec4 eye_space = view * vec4(position, 1.0);
  float distance = -eye_space.z;
  eye_space.xyz *= 1.0 - depth_bias;
  gl_Position = projection * eye_space;
  float far = clamp((distance - fade_start) / max(fade_end - fade_start, 1e-6), 0.0, 1.0);
  line_colour = vec4(vertex_colour.rgb, vertex_colour.a * mix(1.0, far_alpha, far));
}
