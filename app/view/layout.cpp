#include "app/view/layout.h"

#include <algorithm>
#include <cmath>

namespace gs::app {

namespace {

// An undragged panel takes this share of the window, within these bounds.
constexpr float kControlsShare = 0.3f, kControlsDefaultMax = 420.0f;
constexpr float kBottomShare = 0.3f, kBottomDefaultMax = 300.0f;

// One panel's size along a window side of `side` units: the dragged size or the default
// share, kept between the panel's minimum and what leaves the viewport its minimum (a usable
// one after a drag); the panel's minimum wins when the side is too short for both, and
// lay_out_window then gives the viewport kMinViewport and the panel what is left.
float panel_size(float side, float dragged, float share, float min, float default_max) {
  const float wanted = dragged > 0 ? dragged : std::clamp(side * share, min, default_max);
  const float viewport_min = dragged > 0 ? kMinViewportDrag : kMinViewport;
  // Whole units: ImGui floors window positions, so a fractional edge would overlap a bar.
  return std::round(
      std::clamp(wanted, min, std::max(side - kSplitterThickness - viewport_min, min)));
}

}  // namespace

WindowLayout lay_out_window(float width, float height, const SplitterPositions& splitters) {
  const float controls = panel_size(width, splitters.controls_width, kControlsShare,
                                    kControlsMinWidth, kControlsDefaultMax);
  const float bottom = panel_size(height, splitters.bottom_height, kBottomShare, kBottomMinHeight,
                                  kBottomDefaultMax);
  WindowLayout layout;
  const float view_w = std::max(width - controls - kSplitterThickness, kMinViewport);
  const float view_h = std::max(height - bottom - kSplitterThickness, kMinViewport);
  layout.viewport = {0, 0, view_w, view_h};
  layout.right_splitter = {view_w, 0, kSplitterThickness, height};
  // Nothing of negative size in a window too small for the viewport and a bar.
  const float controls_w = std::max(width - view_w - kSplitterThickness, 0.0f);
  const float bottom_h = std::max(height - view_h - kSplitterThickness, 0.0f);
  layout.controls = {view_w + kSplitterThickness, 0, controls_w, height};
  layout.bottom_splitter = {0, view_h, view_w, kSplitterThickness};
  layout.bottom = {0, view_h + kSplitterThickness, view_w, bottom_h};
  return layout;
}

}  // namespace gs::app
