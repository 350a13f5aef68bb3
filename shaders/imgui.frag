#version 330 core
uniform sampler2D atlas;
in vec2 frag_uv;
in vec4 frag_colour;
out vec4 colour;

void main() { colour = frag_colour * texture(atlas, frag_uv); }
