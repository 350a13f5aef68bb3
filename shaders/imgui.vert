#version 330 core
// Dear ImGui's vertices: position in display pixels (top-left origin), texture coordinate
// into the font atlas, colour as 4 normalised bytes (straight alpha).
layout(location = 0) in vec2 position;
layout(location = 1) in vec2 uv;
layout(location = 2) in vec4 vertex_colour;
uniform mat4 projection;
out vec2 frag_uv;
out vec4 frag_colour;

void main() {
  frag_uv = uv;
  frag_colour = vertex_colour;
  gl_Position = projection * vec4(position, 0.0, 1.0);
}
