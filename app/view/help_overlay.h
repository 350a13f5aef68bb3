// The keyboard and mouse help: a window over the viewer listing every control, toggled by
// F1 or `?` (unless a text field has the keyboard) or a script's `key F1`.
#pragma once

namespace gs::app {

class HelpOverlay {
 public:
  void toggle() { shown_ = !shown_; }
  // This frame's F1 or `?`, then the window when shown (its close button hides it).
  void draw();

 private:
  bool shown_ = false, was_shown_ = false;  // was_shown_: in the frame before
};

}  // namespace gs::app
