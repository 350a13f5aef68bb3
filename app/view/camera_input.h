// Everything that moves the camera: the mouse over the viewport (drag to orbit about the
// pivot, shift or middle drag to pan, wheel to dolly, double-click to set the pivot, click to
// pick a walk), the keys (F frames the scene, R resets, W/A/S/D fly), and the controls
// panel's camera section (the camera as text, the fly switch).
#pragma once
#include <cstdint>
#include <span>

#include "app/view/text_field.h"

struct ImGuiIO;

namespace gs::app {

struct ViewState;

// One mouse or keyboard control and what it does, for the help overlay (help_overlay.h).
struct ControlHelp {
  const char* input;
  const char* action;
};

// Every control CameraInput reads, in the order a newcomer needs them.
std::span<const ControlHelp> camera_controls();

class CameraInput {
 public:
  // This frame's mouse and keys, unless a panel has them.
  void update(ViewState& state);
  // The camera section of the controls panel.
  void controls(ViewState& state);

 private:
  void mouse(ViewState& state);
  void drag(ViewState& state, const ImGuiIO& io);
  void keys(ViewState& state);
  void fly_keys(ViewState& state, const ImGuiIO& io);
  void set_pivot_at(ViewState& state, int x, int y);

  int button_ = 0;  // the dragging mouse button: 0 left (orbit), 2 middle (pan)
  bool dragging_ = false, moved_ = false, skip_release_ = false;
  bool fly_ = false;
  TextField<512> camera_text_;
  uint64_t camera_text_of_ = 0;  // the Session::camera_changes() the text shows
};

}  // namespace gs::app
