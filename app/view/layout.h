// Where the viewer's parts sit in the window (no docking in ImGui 1.86): the viewport at the
// top left, the controls panel on the right at full height, the inspector panel below the
// viewport, and between them two splitter bars the user drags. A pure function of the
// window's size and the splitters' positions, so that it is tested without a display.
#pragma once

namespace gs::app {

// In window units (ImGui's), top-left origin.
struct Rect {
  float x = 0, y = 0, w = 0, h = 0;
  float right() const { return x + w; }
  float bottom() const { return y + h; }
};

// The bar between the viewport and the controls panel, or the one above the bottom panel.
enum class Splitter { right, bottom };

// The panel sizes the splitters were dragged to; 0: not dragged yet, so a share of the window.
struct SplitterPositions {
  float controls_width = 0;
  float bottom_height = 0;
};

struct WindowLayout {
  Rect viewport;
  Rect right_splitter;  // between the viewport (and the bottom panel) and the controls
  Rect controls;
  Rect bottom_splitter;  // between the viewport and the bottom panel
  Rect bottom;
};

constexpr float kMinViewport = 16.0f;  // the viewport never shrinks below this
constexpr float kSplitterThickness = 6.0f;
// The controls panel's widgets (sliders with their labels, the camera's text field) stay
// usable down to this width; the bottom panel's tab bar, one navigation row and a few table
// rows fit in this height. A smaller window takes it from the viewport first.
constexpr float kControlsMinWidth = 280.0f, kBottomMinHeight = 180.0f;
// Dragging never shrinks the viewport below this (a window too small for both the panels'
// minimums and this keeps the minimums' share and squeezes the viewport down to 16).
constexpr float kMinViewportDrag = 160.0f;

// The tiling of a width x height window (whole units) for the splitters' positions: the
// viewport, the bars and the panels cover the window without overlapping, edges on whole
// units. Panels that were not dragged take a
// share of the window within bounds; dragged ones keep their size within the minimums above.
WindowLayout lay_out_window(float width, float height, const SplitterPositions& splitters);

}  // namespace gs::app
