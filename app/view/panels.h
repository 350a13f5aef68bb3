// The two panels around the viewport (no docking in ImGui 1.86), where the layout (layout.h)
// puts them. On the right, the controls: the structure, the overlays and heatmap, the camera,
// the scene, and the status line. Below the viewport, three tabs: the walk inspector, the
// statistics and the states table (sortable by any column).
#pragma once
#include "app/view/layout.h"
#include "app/view/states_table.h"

namespace gs::app {

class CameraInput;
class OverlayCache;
class SceneOpener;
class StructureEditor;
struct ViewState;

class Panels {
 public:
  // The parts that draw sections of their own.
  Panels(StructureEditor& structure, OverlayCache& overlays, CameraInput& camera,
         SceneOpener& scene);

  void draw(ViewState& state, const WindowLayout& layout);

 private:
  void controls_panel(ViewState& state, const Rect& rect);
  void bottom_panel(ViewState& state, const Rect& rect);

  StructureEditor& structure_;
  OverlayCache& overlays_;
  CameraInput& camera_;
  SceneOpener& scene_;
  StatesTable states_;
};

}  // namespace gs::app
