#include "app/view/viewport.h"

// glad first: it claims the GL header guard before GLFW or ImGui could pull in GL headers.
#include <glad/gl.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <span>
#include <vector>

#include "app/view/overlay_cache.h"
#include "core/render/render.h"

namespace gs::app {

namespace {

// The viewport never grows beyond this many pixels a side, whatever the window: the renderer
// and the UI hold about 90 bytes per pixel in flight (images, per-pixel records, sums), 1.5 GB
// here.
constexpr int kMaxViewportSide = 4096;

}  // namespace

bool ViewportTarget::resize(int width, int height) {
  if (width == width_ && height == height_) return false;
  release();
  width_ = width, height_ = height;
  glGenTextures(1, &colour_);
  glBindTexture(GL_TEXTURE_2D, colour_);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, width, height, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glGenRenderbuffers(1, &depth_);
  glBindRenderbuffer(GL_RENDERBUFFER, depth_);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width, height);
  glGenFramebuffers(1, &fbo_);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, colour_, 0);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  return true;
}

void ViewportTarget::bind() const { glBindFramebuffer(GL_FRAMEBUFFER, fbo_); }

ImTextureID ViewportTarget::texture() const {
  return reinterpret_cast<ImTextureID>(intptr_t(colour_));
}

void ViewportTarget::release() {
  if (fbo_) glDeleteFramebuffers(1, &fbo_);
  if (depth_) glDeleteRenderbuffers(1, &depth_);
  if (colour_) glDeleteTextures(1, &colour_);
  fbo_ = depth_ = colour_ = 0;
}

ViewportImage::ViewportImage() {
  // The viewport is a texture and a depth renderbuffer: no larger than GL allows either.
  GLint texture = 0, renderbuffer = 0;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &texture);
  glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &renderbuffer);
  max_side_ = std::min({kMaxViewportSide, int(texture), int(renderbuffer)});
}

Viewport ViewportImage::place(const ImGuiIO& io, const Rect& area) const {
  Viewport view;
  view.scale = std::max(io.DisplayFramebufferScale.x, 1.0f);
  const float largest = float(max_side_) / view.scale;
  view.x = area.x, view.y = area.y;
  view.w = std::clamp(area.w, kMinViewport, largest);
  view.h = std::clamp(area.h, kMinViewport, largest);
  return view;
}

bool ViewportImage::draw(const ViewState& state, OverlayCache& overlays) {
  const ViewSetup& setup = state.session.setup();
  const bool new_target = target_.resize(setup.width, setup.height);
  ViewportContent now = content(state, overlays);
  const bool redraw = new_target || !(now == drawn_);
  if (redraw) {
    target_.bind();
    draw_content(state, overlays, now);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    drawn_ = std::move(now);
  }
  // GL textures count rows from the bottom: flip v.
  const Viewport& view = state.viewport;
  ImGui::GetBackgroundDrawList()->AddImage(target_.texture(), ImVec2(view.x, view.y),
                                           ImVec2(view.x + view.w, view.y + view.h), ImVec2(0, 1),
                                           ImVec2(1, 0));
  return redraw;
}

namespace {

// Byte for byte: equal bytes always draw the same lines (a difference only in how a number
// is written, -0 or a NaN, draws them again, which is harmless).
template <class T>
bool same_bytes(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

}  // namespace

bool ViewportContent::operator==(const ViewportContent& other) const {
  if (generation != other.generation || pass != other.pass || width != other.width ||
      height != other.height || has_image != other.has_image || heat_image != other.heat_image ||
      lines.size() != other.lines.size())
    return false;
  for (size_t i = 0; i < lines.size(); ++i)
    if (lines[i].emphasised != other.lines[i].emphasised ||
        !same_bytes(lines[i].vertices, other.lines[i].vertices) ||
        !same_bytes(lines[i].fill, other.lines[i].fill))
      return false;
  return true;
}

ViewportContent ViewportImage::content(const ViewState& state, OverlayCache& overlays) const {
  const ViewSetup& setup = state.session.setup();
  const ProgressiveFrame& frame = state.session.frame();
  ViewportContent content;
  content.generation = frame.generation, content.pass = frame.pass;
  content.width = setup.width, content.height = setup.height;
  const size_t pixels = size_t(frame.width) * size_t(frame.height);
  content.has_image = frame.image.rgba.size() == pixels * 4 && pixels > 0;
  if (!content.has_image) return content;
  if (state.overlays.heat != HeatKind::none && frame.pixels.size() == pixels) {
    overlays.heat().rgba(frame, state.overlays.heat);  // made now if the last one is stale
    content.heat_image = overlays.heat().images_made();
  }
  content.lines = overlays.structure_lines();
  if (state.overlays.walk && !state.picked.lines.vertices.empty())
    content.lines.push_back(state.picked.lines);
  return content;
}

void ViewportImage::draw_content(const ViewState& state, OverlayCache& overlays,
                                 const ViewportContent& content) {
  const ViewSetup& setup = state.session.setup();
  if (!content.has_image) {
    glViewport(0, 0, setup.width, setup.height);
    glClearColor(kBackground[0] / 255.0f, kBackground[1] / 255.0f, kBackground[2] / 255.0f, 1);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    return;
  }
  const ProgressiveFrame& frame = state.session.frame();
  gl::FrameInput input;
  input.image_width = frame.width;
  input.image_height = frame.height;
  input.rgba = content.heat_image != 0
                   ? std::span<const uint8_t>(overlays.heat().rgba(frame, state.overlays.heat))
                   : std::span<const uint8_t>(frame.image.rgba);
  input.distance = state.session.distances();
  input.camera = state.session.frame_camera();
  input.scene_box = setup.scene_box;
  input.lines = content.lines;
  frame_renderer_.draw(setup.width, setup.height, input);
}

}  // namespace gs::app
