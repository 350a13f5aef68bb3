#version 330 core
in vec4 line_colour;
out vec4 colour;

void main() { colour = line_colour; }
