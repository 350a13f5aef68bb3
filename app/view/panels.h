// The two panels around the viewport (no docking in ImGui 1.86), where the layout (layout.h)
// puts them. On the right, the controls: the structure, the overlays and heatmap, the A/B
// comparison, the camera, the scene, and the status line. Below the viewport, three tabs: the walk
// inspector, the statistics and the states table (sortable by any column).
#pragma once
#include <string>

#include "app/view/layout.h"
#include "app/view/states_table.h"

namespace gs::app {

class CameraInput;
class CompareView;
class OverlayCache;
class SceneOpener;
class StructureEditor;
struct ViewState;

// The bottom panel's tabs, left to right.
inline constexpr const char* kBottomTabs[] = {"walk", "statistics", "states"};

class Panels {
 public:
  // The parts that draw sections of their own.
  Panels(StructureEditor& structure, OverlayCache& overlays, CameraInput& camera,
         SceneOpener& scene, CompareView& compare);

  void draw(ViewState& state, const WindowLayout& layout);
  // A script's `tab NAME` (one of kBottomTabs): the bottom panel shows that tab from the next
  // frame.
  void select_tab(const std::string& name);

 private:
  void controls_panel(ViewState& state, const Rect& rect);
  void bottom_panel(ViewState& state, const Rect& rect);
  bool tab(const char* name);

  StructureEditor& structure_;
  OverlayCache& overlays_;
  CameraInput& camera_;
  SceneOpener& scene_;
  CompareView& compare_;
  StatesTable states_;
  std::string tab_asked_;  // by select_tab, until drawn
};

}  // namespace gs::app
