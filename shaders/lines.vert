#version 330 core
// World-space line vertices. Each is pulled toward the eye by a small fraction of its
// distance: that keeps its place on screen exactly (it moves along its own sight line) and
// lets lines lying on a surface win the depth test against that surface, at any scale.
layout(location = 0) in vec3 position;
layout(location = 1) in vec4 vertex_colour;
uniform mat4 view;
uniform mat4 projection;
uniform float depth_bias;
out vec4 line_colour;

void main() {
  vec4 eye_space = view * vec4(position, 1.0);
  eye_space.xyz *= 1.0 - depth_bias;
  gl_Position = projection * eye_space;
  line_colour = vertex_colour;
}
