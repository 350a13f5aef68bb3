#include "app/gl/frame.h"

#include <glad/gl.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <limits>

#include "app/gl/program.h"
#include "app/gl/shaders.h"
#include "core/render/render.h"

namespace gs::gl {

namespace {

// Lines are pulled toward the eye by this fraction of their distance (lines.vert): more than
// the 24-bit depth buffer's resolution over the clip range, less than any visible gap.
constexpr float kLineDepthBias = 0.002f;
// The near plane never comes closer than this fraction of the far one (depth precision).
constexpr float kMinNearFraction = 1e-4f;

void set_texture_sampling(GLuint texture) {
  glBindTexture(GL_TEXTURE_2D, texture);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}

}  // namespace

ClipRange clip_range(const Box& box, const Camera& camera) {
  if (box.empty()) return {};
  const glm::vec3 forward = camera.forward();
  float lo = std::numeric_limits<float>::infinity(), hi = -lo;
  for (int corner = 0; corner < 8; ++corner) {
    const glm::vec3 p((corner & 1) ? box.hi.x : box.lo.x, (corner & 2) ? box.hi.y : box.lo.y,
                      (corner & 4) ? box.hi.z : box.lo.z);
    const float d = glm::dot(p - camera.eye, forward);
    lo = std::min(lo, d);
    hi = std::max(hi, d);
  }
  ClipRange range;
  // Margins: the structure's root box is padded a little beyond the scene box.
  range.far_distance = std::max(hi * 1.01f + 1e-6f * std::abs(hi), 1e-3f);
  range.near_distance = std::max(lo * 0.99f, range.far_distance * kMinNearFraction);
  return range;
}

glm::mat4 view_matrix(const Camera& camera) {
  return glm::lookAt(camera.eye, camera.target, camera.up);
}

glm::mat4 projection_matrix(const Camera& camera, float aspect, const ClipRange& range) {
  return glm::perspective(glm::radians(camera.fov), aspect, range.near_distance,
                          range.far_distance);
}

FrameRenderer::FrameRenderer()
    : image_program_(std::make_unique<Program>("image", shaders::image_vert, shaders::image_frag)),
      lines_program_(std::make_unique<Program>("lines", shaders::lines_vert, shaders::lines_frag)) {
  glGenVertexArrays(1, &empty_vao_);  // core profile draws need a VAO even without buffers
  glGenVertexArrays(1, &lines_vao_);
  glGenBuffers(1, &lines_vbo_);
  glBindVertexArray(lines_vao_);
  glBindBuffer(GL_ARRAY_BUFFER, lines_vbo_);
  glEnableVertexAttribArray(0);
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(LineVertex),
                        reinterpret_cast<const void*>(offsetof(LineVertex, position)));
  glVertexAttribPointer(1, 4, GL_FLOAT, GL_FALSE, sizeof(LineVertex),
                        reinterpret_cast<const void*>(offsetof(LineVertex, color)));
  glBindVertexArray(0);
  glGenTextures(1, &colour_texture_);
  glGenTextures(1, &distance_texture_);
  set_texture_sampling(colour_texture_);
  set_texture_sampling(distance_texture_);
}

FrameRenderer::~FrameRenderer() {
  glDeleteTextures(1, &distance_texture_);
  glDeleteTextures(1, &colour_texture_);
  glDeleteBuffers(1, &lines_vbo_);
  glDeleteVertexArrays(1, &lines_vao_);
  glDeleteVertexArrays(1, &empty_vao_);
}

void FrameRenderer::draw(int viewport_width, int viewport_height, const FrameInput& input) {
  const ClipRange range = clip_range(input.scene_box, input.camera);
  const float aspect = float(input.image_width) / float(input.image_height);
  const glm::mat4 projection = projection_matrix(input.camera, aspect, range);
  glViewport(0, 0, viewport_width, viewport_height);
  glDisable(GL_SCISSOR_TEST);
  glDepthMask(GL_TRUE);
  glClearColor(kBackground[0] / 255.0f, kBackground[1] / 255.0f, kBackground[2] / 255.0f, 1.0f);
  glClearDepth(1.0);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  draw_image(viewport_width, viewport_height, input, projection, range);
  draw_lines(input, projection);
}

// The image as a full-viewport triangle; its fragments write the depth of their pixel's
// surface (image.frag) with the depth test on but always passing.
void FrameRenderer::draw_image(int viewport_width, int viewport_height, const FrameInput& input,
                               const glm::mat4& projection, const ClipRange& range) {
  const bool has_distance = !input.distance.empty();
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, colour_texture_);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, input.image_width, input.image_height, 0, GL_RGBA,
               GL_UNSIGNED_BYTE, input.rgba.data());
  glActiveTexture(GL_TEXTURE1);
  glBindTexture(GL_TEXTURE_2D, distance_texture_);
  const float none = std::numeric_limits<float>::infinity();
  glTexImage2D(GL_TEXTURE_2D, 0, GL_R32F, has_distance ? input.image_width : 1,
               has_distance ? input.image_height : 1, 0, GL_RED, GL_FLOAT,
               has_distance ? input.distance.data() : &none);
  const Program& program = *image_program_;
  glUseProgram(program.id());
  glUniform1i(program.uniform("colour_image"), 0);
  glUniform1i(program.uniform("distance_image"), 1);
  glUniform2f(program.uniform("viewport_size"), float(viewport_width), float(viewport_height));
  glUniformMatrix4fv(program.uniform("projection"), 1, GL_FALSE, glm::value_ptr(projection));
  glUniform1f(program.uniform("far_distance"), range.far_distance);
  glUniform1i(program.uniform("has_distance"), has_distance ? 1 : 0);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_ALWAYS);
  glDisable(GL_BLEND);
  glBindVertexArray(empty_vao_);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glActiveTexture(GL_TEXTURE0);
}

void FrameRenderer::draw_lines(const FrameInput& input, const glm::mat4& projection) {
  std::vector<LineVertex> vertices;
  for (const LineSet& set : input.lines)
    vertices.insert(vertices.end(), set.vertices.begin(),
                    set.vertices.end() - set.vertices.size() % 2);
  if (vertices.empty()) return;
  glBindVertexArray(lines_vao_);
  glBindBuffer(GL_ARRAY_BUFFER, lines_vbo_);
  glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(vertices.size() * sizeof(LineVertex)), vertices.data(),
               GL_STREAM_DRAW);
  const Program& program = *lines_program_;
  glUseProgram(program.id());
  const glm::mat4 view = view_matrix(input.camera);
  glUniformMatrix4fv(program.uniform("view"), 1, GL_FALSE, glm::value_ptr(view));
  glUniformMatrix4fv(program.uniform("projection"), 1, GL_FALSE, glm::value_ptr(projection));
  glUniform1f(program.uniform("depth_bias"), kLineDepthBias);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glEnable(GL_BLEND);
  glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
  glDrawArrays(GL_LINES, 0, GLsizei(vertices.size()));
  glDisable(GL_BLEND);
  glDisable(GL_DEPTH_TEST);
  glBindVertexArray(0);
}

std::vector<uint8_t> read_pixels(int width, int height) {
  const size_t row = size_t(width) * 4;
  std::vector<uint8_t> bottom_up(row * size_t(height)), top_down(bottom_up.size());
  glFinish();
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, bottom_up.data());
  for (int y = 0; y < height; ++y)
    std::memcpy(top_down.data() + size_t(y) * row, bottom_up.data() + size_t(height - 1 - y) * row,
                row);
  return top_down;
}

}  // namespace gs::gl
