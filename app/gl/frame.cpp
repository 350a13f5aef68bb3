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
// Thin lines at the far end of the scene box keep this fraction of their opacity.
constexpr float kFarLineAlpha = 0.3f;
// Emphasised lines (the walk), in framebuffer pixels.
constexpr float kThickLineWidth = 3.0f;

void set_texture_sampling(GLuint texture) {
  glBindTexture(GL_TEXTURE_2D, texture);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}

// Where `p` lands in clip space, pulled toward the eye as lines.vert pulls it.
glm::vec4 to_clip(const glm::mat4& view, const glm::mat4& projection, glm::vec3 p) {
  glm::vec4 eye_space = view * glm::vec4(p, 1.0f);
  eye_space = glm::vec4(glm::vec3(eye_space) * (1.0f - kLineDepthBias), 1.0f);
  return projection * eye_space;
}

// Cuts the clip-space segment a-b at the near plane (z = -w); false when it lies wholly in
// front of it. A walk's ray starts at the eye, where w is 0 and no division is possible.
bool clip_to_near(glm::vec4& a, glm::vec4& b) {
  const float da = a.z + a.w, db = b.z + b.w;  // >= 0 beyond the near plane
  if (da < 0.0f && db < 0.0f) return false;
  if (da < 0.0f) a = glm::mix(a, b, da / (da - db));
  if (db < 0.0f) b = glm::mix(b, a, db / (db - da));
  return true;
}

// The segments as quads `width` pixels wide in normalised device coordinates (two triangles
// each, lengthened by half the width so that box corners close): GL 3.3 core profiles need
// not draw lines wider than one pixel (glLineWidth), and Mesa's do not.
std::vector<LineVertex> thick_quads(std::span<const LineVertex> segments, const glm::mat4& view,
                                    const glm::mat4& projection, glm::vec2 viewport_size,
                                    float width) {
  std::vector<LineVertex> quads;
  const glm::vec2 ndc_per_pixel = 2.0f / viewport_size;
  for (size_t i = 0; i + 1 < segments.size(); i += 2) {
    glm::vec4 a = to_clip(view, projection, segments[i].position);
    glm::vec4 b = to_clip(view, projection, segments[i + 1].position);
    if (!clip_to_near(a, b)) continue;
    const glm::vec3 na = glm::vec3(a) / a.w, nb = glm::vec3(b) / b.w;
    glm::vec2 along = (glm::vec2(nb) - glm::vec2(na)) / ndc_per_pixel;  // in pixels
    const float length = glm::length(along);
    along = length > 1e-6f ? along / length : glm::vec2(1.0f, 0.0f);
    const glm::vec2 half_along = along * (0.5f * width) * ndc_per_pixel;
    const glm::vec2 half_across = glm::vec2(-along.y, along.x) * (0.5f * width) * ndc_per_pixel;
    const glm::vec3 corners[4] = {glm::vec3(glm::vec2(na) - half_along - half_across, na.z),
                                  glm::vec3(glm::vec2(na) - half_along + half_across, na.z),
                                  glm::vec3(glm::vec2(nb) + half_along + half_across, nb.z),
                                  glm::vec3(glm::vec2(nb) + half_along - half_across, nb.z)};
    const glm::vec4 colours[4] = {segments[i].color, segments[i].color, segments[i + 1].color,
                                  segments[i + 1].color};
    for (const int k : {0, 1, 2, 0, 2, 3}) quads.push_back({corners[k], colours[k]});
  }
  return quads;
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
  const LineBatches lines = batch_lines(input.lines);
  // Depth only matters to lines: without them the image is drawn with no depth test, so that
  // no fragment writes a depth (Mesa's CPU renderer took ~30 ms a 1274x794 frame with it).
  const bool any_lines = !lines.thin.empty() || !lines.fill.empty() || !lines.thick.empty();
  draw_image(viewport_width, viewport_height, input, projection, range, any_lines);
  if (any_lines)
    draw_lines(lines, input, projection, range, glm::vec2(viewport_width, viewport_height));
}

FrameRenderer::LineBatches FrameRenderer::batch_lines(std::span<const LineSet> sets) {
  LineBatches batches;
  for (const LineSet& set : sets) {
    std::vector<LineVertex>& into = set.emphasised ? batches.thick : batches.thin;
    into.insert(into.end(), set.vertices.begin(), set.vertices.end() - set.vertices.size() % 2);
    batches.fill.insert(batches.fill.end(), set.fill.begin(), set.fill.end() - set.fill.size() % 3);
  }
  return batches;
}

// The image as a full-viewport triangle; with `depth`, its fragments write the depth of their
// pixel's surface (image.frag) with the depth test on but always passing.
void FrameRenderer::draw_image(int viewport_width, int viewport_height, const FrameInput& input,
                               const glm::mat4& projection, const ClipRange& range, bool depth) {
  const bool has_distance = depth && !input.distance.empty();
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
  if (depth)
    glEnable(GL_DEPTH_TEST);
  else
    glDisable(GL_DEPTH_TEST);
  glDepthFunc(GL_ALWAYS);
  glDisable(GL_BLEND);
  glBindVertexArray(empty_vao_);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glActiveTexture(GL_TEXTURE0);
}

// Thin sets first, fading with distance; then the emphasised ones (the walk) over them at
// full strength: fills, then thick lines. All depth-tested against the image only (no depth
// writes), so that lines never hide one another.
void FrameRenderer::draw_lines(const LineBatches& lines, const FrameInput& input,
                               const glm::mat4& projection, const ClipRange& range,
                               glm::vec2 viewport_size) {
  const glm::mat4 view = view_matrix(input.camera);
  const Program& program = *lines_program_;
  glUseProgram(program.id());
  const auto set_transform = [&](const glm::mat4& v, const glm::mat4& p, float bias) {
    glUniformMatrix4fv(program.uniform("view"), 1, GL_FALSE, glm::value_ptr(v));
    glUniformMatrix4fv(program.uniform("projection"), 1, GL_FALSE, glm::value_ptr(p));
    glUniform1f(program.uniform("depth_bias"), bias);
  };
  set_transform(view, projection, kLineDepthBias);
  glUniform1f(program.uniform("fade_start"), range.near_distance);
  glUniform1f(program.uniform("fade_end"), range.far_distance);
  glUniform1f(program.uniform("far_alpha"), kFarLineAlpha);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_FALSE);
  glEnable(GL_BLEND);
  glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
  draw_vertices(lines.thin, GL_LINES);
  glUniform1f(program.uniform("far_alpha"), 1.0f);
  draw_vertices(lines.fill, GL_TRIANGLES);
  // The thick quads are already in device coordinates (thick_quads applies the bias).
  const std::vector<LineVertex> quads =
      thick_quads(lines.thick, view, projection, viewport_size, kThickLineWidth);
  set_transform(glm::mat4(1.0f), glm::mat4(1.0f), 0.0f);
  draw_vertices(quads, GL_TRIANGLES);
  glDepthMask(GL_TRUE);
  glDisable(GL_BLEND);
  glDisable(GL_DEPTH_TEST);
  glBindVertexArray(0);
}

void FrameRenderer::draw_vertices(std::span<const LineVertex> vertices, unsigned mode) {
  if (vertices.empty()) return;
  glBindVertexArray(lines_vao_);
  glBindBuffer(GL_ARRAY_BUFFER, lines_vbo_);
  glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(vertices.size() * sizeof(LineVertex)), vertices.data(),
               GL_STREAM_DRAW);
  glDrawArrays(GLenum(mode), 0, GLsizei(vertices.size()));
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
