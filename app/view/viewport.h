// The viewport: where the image goes for the window's size, and drawing the shown frame
// there. The frame (image or heatmap, line overlays depth-tested against the image's
// distances) is drawn by gl::FrameRenderer into a texture of its own, shown under the panels.
#pragma once
#include <imgui.h>

#include "app/gl/frame.h"
#include "app/view/layout.h"
#include "app/view/state.h"

namespace gs::app {

class OverlayCache;

// The viewport's own framebuffer. FrameRenderer draws at (0, 0) of the current framebuffer
// and its image shader maps gl_FragCoord to texels, so the frame is drawn here and shown in
// the window as an image under the panels.
class ViewportTarget {
 public:
  ViewportTarget() = default;
  ~ViewportTarget() { release(); }
  ViewportTarget(const ViewportTarget&) = delete;
  ViewportTarget& operator=(const ViewportTarget&) = delete;

  void resize(int width, int height);
  void bind() const;
  ImTextureID texture() const;

 private:
  void release();
  unsigned fbo_ = 0, colour_ = 0, depth_ = 0;
  int width_ = 0, height_ = 0;
};

class ViewportImage {
 public:
  ViewportImage();  // needs the window's GL context

  // The viewport in the layout's `area` (layout.h), within what GL can hold.
  Viewport place(const ImGuiIO& io, const Rect& area) const;
  // The shown frame with the overlays chosen, at the viewport's place.
  void draw(const ViewState& state, OverlayCache& overlays);

 private:
  void draw_frame(const ViewState& state, OverlayCache& overlays);

  gl::FrameRenderer frame_renderer_;
  ViewportTarget target_;
  int max_side_ = 0;  // pixels a side
};

}  // namespace gs::app
