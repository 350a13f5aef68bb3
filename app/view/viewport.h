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

  // True when it made a new texture (its contents are undefined until drawn).
  bool resize(int width, int height);
  void bind() const;
  ImTextureID texture() const;

 private:
  void release();
  unsigned fbo_ = 0, colour_ = 0, depth_ = 0;
  int width_ = 0, height_ = 0;
};

// What the viewport's texture shows. Mesa's CPU renderer takes about 30 ms to upload and draw a
// 1274x794 frame, on the cores the progressive renderer traces on, so the texture is drawn
// again only when one of these changes; the UI's other frames show it as it is.
struct ViewportContent {
  uint64_t generation = 0;  // the progressive frame (its image, distances and camera)
  int pass = -1;
  int width = 0, height = 0;   // the view's size
  bool has_image = false;      // false: the view is cleared (no frame of its size yet)
  uint64_t heat_image = 0;     // HeatMap::images_made of the heat image shown; 0: the render
  std::vector<LineSet> lines;  // the overlays
  bool operator==(const ViewportContent& other) const;
};

class ViewportImage {
 public:
  ViewportImage();  // needs the window's GL context

  // The viewport in the layout's `area` (layout.h), within what GL can hold.
  Viewport place(const ImGuiIO& io, const Rect& area) const;
  // The shown frame with the overlays chosen, at the viewport's place. True when the
  // viewport's texture was drawn anew (the window must then be drawn again).
  bool draw(const ViewState& state, OverlayCache& overlays);

 private:
  ViewportContent content(const ViewState& state, OverlayCache& overlays) const;
  void draw_content(const ViewState& state, OverlayCache& overlays, const ViewportContent& content);

  gl::FrameRenderer frame_renderer_;
  ViewportContent drawn_;
  ViewportTarget target_;
  int max_side_ = 0;  // pixels a side
};

}  // namespace gs::app
