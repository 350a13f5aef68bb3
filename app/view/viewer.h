// The viewer's window and its frame loop, in the shape of Dear ImGui's example main loop:
// poll events, new frame, build the UI, render, swap. The parts it runs every frame (script,
// camera input, overlay cache, viewport, panels) share one ViewState.
#pragma once
#include <memory>
#include <vector>

#include "app/gl/imgui_renderer.h"
#include "app/gl/window.h"
#include "app/view/camera_input.h"
#include "app/view/compare_view.h"
#include "app/view/help_overlay.h"
#include "app/view/layout.h"
#include "app/view/overlay_cache.h"
#include "app/view/panels.h"
#include "app/view/scene_opener.h"
#include "app/view/script.h"
#include "app/view/splitters.h"
#include "app/view/state.h"
#include "app/view/structure_editor.h"
#include "app/view/view.h"
#include "app/view/viewport.h"

namespace gs::app {

class Viewer {
 public:
  // Opens the window (InputError without an OpenGL 3.3 context).
  Viewer(const ViewJob& job, std::shared_ptr<const Scene> scene, std::vector<ScriptStep> steps);

  // One frame per turn until the window closes or the script is done. A minimised window
  // draws nothing (no 0x0 viewport, texture or render) but still counts frames, runs script
  // steps and takes loads and passes.
  void run();

 private:
  void run_due_steps();
  void run_step(const ScriptStep& step);
  void take_frame();
  // False when the frame would look as the window does: then nothing is drawn.
  bool draw_frame();
  bool build_ui();  // true when a texture the UI shows was drawn anew
  void lay_out();
  Camera initial_camera(int width, int height) const;
  void render();

  const ViewJob& job_;
  gl::Window window_;  // first: the GL context outlives every GL object below
  gl::ImGuiRenderer imgui_renderer_;
  gl::DrawDataRecord drawn_ui_;  // the draw data the window shows
  ViewportImage viewport_;
  ViewState state_;      // holds the renderer: its destructor stops the workers
  CompareView compare_;  // B's renderer and its GL objects
  SceneOpener scene_;    // its destructor waits for a load in progress
  Script script_;
  CameraInput camera_input_;
  OverlayCache overlays_;
  StructureEditor structure_;
  Panels panels_;
  Splitters splitters_;
  WindowLayout layout_;  // this frame's
  HelpOverlay help_;
};

}  // namespace gs::app
