// The two bars between the viewport and the panels (layout.h), drawn as small windows of
// their own on top of the panels' edges' gap. Dragging one moves it; the next frame's layout
// gives the viewport the new size, which restarts the renderer as a window resize does.
#pragma once
#include <imgui.h>

#include "app/view/layout.h"

namespace gs::app {

class Splitters {
 public:
  // The window's layout with the splitters where they were left, after the moves asked.
  WindowLayout lay_out(const ImVec2& display);
  // Both bars of `layout`, taking this frame's drags.
  void draw(const WindowLayout& layout);
  // A script's drag: the next lay_out moves the bar by `pixels` (right or down).
  void ask_move(Splitter which, float pixels) { asked_[int(which)] += pixels; }

 private:
  // Moves a bar by `pixels` (right or down), as a drag of that many units does: the
  // viewport grows by as much, within the panels' and the viewport's minimums.
  void move(Splitter which, float pixels, const WindowLayout& layout);
  void bar(const char* name, const Rect& rect, Splitter which, const WindowLayout& layout);

  SplitterPositions positions_;
  float asked_[2] = {0, 0};  // by Splitter
};

}  // namespace gs::app
