#version 330 core
// The CPU-rendered image, one texel per pixel read with texelFetch (no filtering, so the
// frame shows exactly what `gridscope render` wrote), and its depth: the pixel's distance
// along the camera's forward axis put through the projection the lines use, so that lines
// behind a surface fail the depth test.
uniform sampler2D colour_image;    // RGBA8, row 0 = the top of the image
uniform sampler2D distance_image;  // R32F view-axis distance, +inf for background
uniform vec2 viewport_size;
uniform mat4 projection;
uniform float far_distance;
uniform bool has_distance;
out vec4 colour;

void main() {
  ivec2 size = textureSize(colour_image, 0);
  // Window row 0 is the bottom; the image's row 0 is the top.
  vec2 from_top = vec2(gl_FragCoord.x, viewport_size.y - gl_FragCoord.y);
  ivec2 texel = clamp(ivec2(from_top * vec2(size) / viewport_size), ivec2(0), size - 1);
  colour = texelFetch(colour_image, texel, 0);
  float d = has_distance ? texelFetch(distance_image, texel, 0).r : far_distance;
  if (!(d < far_distance)) {  // no distances, background, beyond the far plane, or NaN
    gl_FragDepth = 1.0;
    return;
  }
  vec4 clip = projection * vec4(0.0, 0.0, -d, 1.0);
  gl_FragDepth = clamp(clip.z / clip.w * 0.5 + 0.5, 0.0, 1.0);
}
