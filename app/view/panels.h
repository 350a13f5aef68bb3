// The two panels around the viewport (no docking in ImGui 1.86). On the right, the controls:
// the structure, the overlays and heatmap, the A/B comparison, the camera, the scene, and the
// status line. Below
// the viewport, three tabs: the walk inspector, the statistics and the states table.
#pragma once

namespace gs::app {

class CameraInput;
class CompareView;
class OverlayCache;
class SceneOpener;
class StructureEditor;
struct ViewState;

class Panels {
 public:
  // The parts that draw sections of their own.
  Panels(StructureEditor& structure, OverlayCache& overlays, CameraInput& camera,
         SceneOpener& scene, CompareView& compare);

  void draw(ViewState& state);

 private:
  void controls_panel(ViewState& state);
  void bottom_panel(ViewState& state);

  StructureEditor& structure_;
  OverlayCache& overlays_;
  CameraInput& camera_;
  SceneOpener& scene_;
  CompareView& compare_;
};

}  // namespace gs::app
