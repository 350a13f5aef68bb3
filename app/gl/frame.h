// The frame `gridscope shot` and the viewer both draw: the CPU-rendered image (or a heat
// image in its place) filling the viewport, and line overlays in world space on top,
// depth-tested against the image's own per-pixel distances so that lines behind a surface
// are hidden. Needs a current GL 3.3 context with glad loaded.
#pragma once
#include <cstdint>
#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <memory>
#include <span>
#include <vector>

#include "core/render/overlay.h"
#include "core/scene/camera.h"
#include "core/scene/scene.h"

namespace gs::gl {

class Program;

// Near and far planes that hold the whole scene box in front of the camera (the near plane
// is kept at a small fraction of the far one when the eye is inside the box).
struct ClipRange {
  float near_distance = 0.01f;
  float far_distance = 100.0f;
};
ClipRange clip_range(const Box& box, const Camera& camera);

// The matrices under which world points land on the pixels `Camera::primary_ray` shoots
// through, for an image of this aspect (width / height).
glm::mat4 view_matrix(const Camera& camera);
glm::mat4 projection_matrix(const Camera& camera, float aspect, const ClipRange& range);

struct FrameInput {
  int image_width = 0;
  int image_height = 0;
  std::span<const uint8_t> rgba;    // image_width * image_height * 4, rows from the top
  std::span<const float> distance;  // per pixel along camera.forward(), +inf for background;
                                    // empty: no depth, lines are drawn over everything
  Camera camera;
  Box scene_box;                   // chooses the near and far planes
  std::span<const LineSet> lines;  // emphasised sets are drawn after the others
};

class FrameRenderer {
 public:
  FrameRenderer();
  ~FrameRenderer();
  FrameRenderer(const FrameRenderer&) = delete;
  FrameRenderer& operator=(const FrameRenderer&) = delete;

  // Draws into the current framebuffer's (0, 0, width, height), the image stretched over it
  // texel by texel (nearest; exact when the viewport has the image's size).
  void draw(int viewport_width, int viewport_height, const FrameInput& input);

 private:
  void draw_image(int viewport_width, int viewport_height, const FrameInput& input,
                  const glm::mat4& projection, const ClipRange& range, bool depth);
  // The sets' vertices gathered by how they are drawn (whole segments and triangles only).
  struct LineBatches {
    std::vector<LineVertex> thin, fill, thick;
  };
  static LineBatches batch_lines(std::span<const LineSet> sets);
  void draw_lines(const LineBatches& lines, const FrameInput& input, const glm::mat4& projection,
                  const ClipRange& range, glm::vec2 viewport_size);
  // Sends `vertices` through the lines program as `mode` primitives.
  void draw_vertices(std::span<const LineVertex> vertices, unsigned mode);

  std::unique_ptr<Program> image_program_, lines_program_;
  unsigned empty_vao_ = 0, lines_vao_ = 0, lines_vbo_ = 0;
  unsigned colour_texture_ = 0, distance_texture_ = 0;
};

// The current framebuffer's (0, 0, width, height) as RGBA8 rows from the top (GL counts
// rows from the bottom), ready for write_png.
std::vector<uint8_t> read_pixels(int width, int height);

}  // namespace gs::gl
