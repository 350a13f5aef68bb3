#include "app/view/viewer.h"

// glad first: it claims the GL header guard before GLFW or ImGui could pull in GL headers.
#include <glad/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>

#include <cfloat>
#include <glm/trigonometric.hpp>
#include <utility>

#include "app/view/build_progress.h"
#include "app/view/output.h"
#include "app/view/overlay_panel.h"
#include "core/render/camera_control.h"

namespace gs::app {

namespace {

// The close-up of lumpy's cluster the README's pictures use.
constexpr const char* kCloseUp = "eye=3.2,-4.2,2.2;target=0,0,0.35;up=0,0,1;fov=40";
constexpr double kIdleWait = 0.05;  // seconds a minimised window sleeps per frame
// The longest a frame waits for input or a finished pass before drawing again (either ends
// the wait at once).
// Drawing without a pause redrew the same image hundreds of times a second through Mesa's
// CPU renderer, taking half of the cores from the progressive renderer (the first full pass
// of lumpy's close-up at 1280x800 took 1.2-1.5 s instead of 0.55 s).
constexpr double kFrameWait = 1.0 / 30.0;

}  // namespace

Viewer::Viewer(const ViewJob& job, std::shared_ptr<const Scene> scene,
               std::vector<ScriptStep> steps)
    : job_(job),
      window_(job.width, job.height, "gridscope view"),
      // A finished pass ends the frame's wait for input (glfwPostEmptyEvent: any thread).
      state_(scene, job.accel, job.params, job.overlays, [] { glfwPostEmptyEvent(); }),
      compare_([] { glfwPostEmptyEvent(); }),
      scene_(scene->name),
      script_(job, std::move(steps)),
      structure_(job.accel, job.params),
      panels_(structure_, overlays_, camera_input_, scene_, compare_) {
  if (script_.scripted()) glfwSwapInterval(0);  // scripts need no vsync
  state_.session.set_packets(job.packets);
  state_.session.set_max_spp(job.max_spp);
  if (!job.compare.empty()) compare_.set(state_, job.compare);
}

void Viewer::run() {
  while (!window_.should_close()) {
    window_.wait_events(kFrameWait);
    run_due_steps();
    scene_.take_loaded(state_);
    take_frame();
    const bool shown = !window_.minimised();
    bool drawn = false;
    if (shown) {
      drawn = draw_frame();
      ++state_.frames_built;
      if (drawn) ++state_.frames_drawn;
    } else {
      window_.wait_events(kIdleWait);
    }
    if (script_.frame_done(state_, scene_.pending().has_value())) {
      if (!job_.screenshot.empty()) {
        if (shown && !drawn) render();  // the back buffer holds nothing after a swap
        write_screenshot(window_, job_.screenshot);
      }
      break;
    }
    if (drawn) window_.swap();
  }
  window_.hide();  // gone at once, while the workers finish their rows
  if (!job_.stats.empty()) write_stats(state_, compare_.stats(state_), job_.stats);
}

void Viewer::run_due_steps() {
  while (const ScriptStep* step = script_.next_due_step(state_)) run_step(*step);
}

void Viewer::run_step(const ScriptStep& step) {
  switch (step.action) {
    case ScriptStep::Action::resize:
      window_.resize(step.size[0], step.size[1]);
      break;
    case ScriptStep::Action::open:
      scene_.open(step.name);
      break;
    case ScriptStep::Action::set:
      if (step.name == "overlay")
        choose_overlays(state_, overlays_.heat(), parse_overlays(step.value));
      else if (step.name == "compare")
        compare_.set(state_, step.value);
      else if (step.name == "compare-view")
        compare_.set_mode(*compare_mode_named(step.value));  // checked by parse_script
      else
        structure_.set(state_, step.name, step.value);
      break;
    case ScriptStep::Action::orbit:
      state_.session.move_camera(
          orbit(state_.session.setup().camera, state_.pivot, glm::radians(step.degrees), 0.0f));
      break;
    case ScriptStep::Action::drag_splitter:
      splitters_.ask_move(step.splitter, float(step.pixels));
      break;
    case ScriptStep::Action::help_key:
      help_.toggle();
      break;
    case ScriptStep::Action::tab:
      panels_.select_tab(step.name);
      break;
    case ScriptStep::Action::wait:  // Script::next_due_step held it until it was due
      break;
    case ScriptStep::Action::close:
      window_.close();
      break;
  }
}

void Viewer::take_frame() {
  if (state_.session.take_frame()) script_.check_frame(state_.session.frame());
}

// A frame that would draw what the window already shows leaves it as it is: no drawing, no
// swap (ImGui's draw data and the textures it draws are the same as last time).
bool Viewer::draw_frame() {
  window_.begin_frame();
  // A script drives the viewer without a person: the pointer is ignored, so wherever the
  // display leaves it (Xvfb: its centre) it hovers no widget whose tooltip would cover the
  // viewport in a screenshot.
  if (script_.scripted()) ImGui::GetIO().MousePos = ImVec2(-FLT_MAX, -FLT_MAX);
  ImGui::NewFrame();
  const bool textures_drawn = build_ui();
  ImGui::Render();
  const bool ui_changed = drawn_ui_.changed(ImGui::GetDrawData());
  if (!window_.take_refresh_request() && !textures_drawn && !ui_changed) return false;
  render();
  return true;
}

bool Viewer::build_ui() {
  lay_out();
  script_.click(state_);
  camera_input_.update(state_);
  overlays_.refresh(state_);
  compare_.update(state_, overlays_.heat());
  bool textures_drawn = viewport_.draw(state_, overlays_);
  textures_drawn |= compare_.draw(state_, overlays_.heat());
  panels_.draw(state_, layout_);
  splitters_.draw(layout_);
  help_.draw();
  draw_build_progress(state_);
  return textures_drawn;
}

// Places the viewport and panels for the window's current size and the splitters; a new
// viewport size restarts the renderer at that size, from the starting camera the first time.
void Viewer::lay_out() {
  const ImGuiIO& io = ImGui::GetIO();
  layout_ = splitters_.lay_out(io.DisplaySize);
  state_.viewport = viewport_.place(io, layout_.viewport);
  const int width = int(state_.viewport.w * state_.viewport.scale);
  const int height = int(state_.viewport.h * state_.viewport.scale);
  const ViewSetup& setup = state_.session.setup();
  if (width == setup.width && height == setup.height) return;
  if (!state_.start_camera) {
    state_.start_camera = initial_camera(width, height);
    // The renderer has no size yet, so this only sets the camera: the resize starts it.
    state_.place_camera(*state_.start_camera);
  }
  state_.session.resize(width, height);
}

Camera Viewer::initial_camera(int width, int height) const {
  if (job_.camera) return *job_.camera;
  if (job_.scene.empty()) return parse_camera(kCloseUp);
  return frame_box(state_.session.setup().scene_box, float(width) / float(height));
}

void Viewer::render() {
  const glm::ivec2 size = window_.framebuffer_size();
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glViewport(0, 0, size.x, size.y);
  glClearColor(0.1f, 0.1f, 0.12f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  imgui_renderer_.draw(ImGui::GetDrawData());
}

}  // namespace gs::app
