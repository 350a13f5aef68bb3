#include "app/view/camera_input.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>

#include <cmath>
#include <glm/geometric.hpp>
#include <optional>
#include <string>

#include "app/view/state.h"
#include "core/base/error.h"
#include "core/render/camera_control.h"

namespace gs::app {

namespace {

constexpr float kOrbitSpeed = 0.006f;  // radians per pixel dragged
constexpr float kDollyStep = 0.9f;     // distance kept per wheel notch
constexpr float kFlySpeed = 0.8f;      // eye-to-target distances per second

// What mouse(), drag(), keys() and fly_keys() below do; keep the two in step.
constexpr ControlHelp kCameraControls[] = {
    {"click the image", "inspect that pixel's ray walk (bottom panel, walk tab)"},
    {"drag", "orbit about the pivot"},
    {"shift+drag or middle drag", "pan"},
    {"wheel", "dolly toward or away from the target"},
    {"double-click", "move the pivot (and target) to the surface there"},
    {"F", "frame the whole scene"},
    {"R", "reset to the starting view"},
    {"W / S, A / D", "fly forward / back, left / right (fly switched on)"},
};

}  // namespace

std::span<const ControlHelp> camera_controls() { return kCameraControls; }

void CameraInput::update(ViewState& state) {
  mouse(state);
  keys(state);
}

void CameraInput::mouse(ViewState& state) {
  const ImGuiIO& io = ImGui::GetIO();
  const bool over = state.viewport.contains(io.MousePos) && !io.WantCaptureMouse;
  if (over && ImGui::IsMouseDoubleClicked(0)) {
    const auto [x, y] = state.pixel_at(io.MousePos);
    set_pivot_at(state, x, y);
    skip_release_ = true;
  } else if (over && (ImGui::IsMouseClicked(0) || ImGui::IsMouseClicked(2))) {
    button_ = ImGui::IsMouseClicked(2) ? 2 : 0;
    dragging_ = true;
  }
  if (dragging_) drag(state, io);
  if (over && io.MouseWheel != 0.0f)
    state.session.move_camera(
        dolly(state.session.setup().camera, 1.0f - std::pow(kDollyStep, io.MouseWheel)));
}

void CameraInput::drag(ViewState& state, const ImGuiIO& io) {
  const ImVec2 d = io.MouseDelta;
  const Camera& camera = state.session.setup().camera;
  moved_ = moved_ || ImGui::IsMouseDragging(button_);
  if ((d.x != 0.0f || d.y != 0.0f) && moved_) {
    if (button_ == 0 && !io.KeyShift)
      state.session.move_camera(orbit(camera, state.pivot, -d.x * kOrbitSpeed, -d.y * kOrbitSpeed));
    else
      // camera_control's pan moves the view by minus the drag, y up: the scene follows.
      state.session.move_camera(pan(camera, -d.x / state.viewport.h, d.y / state.viewport.h));
  }
  if (!ImGui::IsMouseReleased(button_)) return;
  // A press and release without a drag is a click: pick that pixel's walk.
  if (button_ == 0 && !skip_release_ && !moved_ && state.viewport.contains(io.MousePos)) {
    const auto [x, y] = state.pixel_at(io.MousePos);
    state.pick(x, y);
  }
  dragging_ = skip_release_ = moved_ = false;
}

// Double-click: the pivot (and target) moves to the surface under the cursor.
void CameraInput::set_pivot_at(ViewState& state, int x, int y) {
  if (!state.structure_ready()) return;
  const std::optional<Walk> walk = state.session.record_walk(x, y);
  if (!walk || !walk->hit.found()) {
    state.status.set(walk ? "pivot: nothing under the cursor"
                          : "pivot: needs a structure with cells");
    return;
  }
  Camera camera = state.session.setup().camera;
  camera.target = walk->ray.origin + walk->hit.t * walk->ray.dir;
  state.place_camera(camera);
}

void CameraInput::keys(ViewState& state) {
  const ImGuiIO& io = ImGui::GetIO();
  if (io.WantCaptureKeyboard) return;
  const ViewSetup& setup = state.session.setup();
  if (ImGui::IsKeyPressed(GLFW_KEY_F, false))
    state.place_camera(frame_box(setup.scene_box, float(setup.width) / setup.height));
  if (ImGui::IsKeyPressed(GLFW_KEY_R, false) && state.start_camera)
    state.place_camera(*state.start_camera);
  if (fly_) fly_keys(state, io);
}

void CameraInput::fly_keys(ViewState& state, const ImGuiIO& io) {
  const auto axis = [](int plus, int minus) {
    return float(ImGui::IsKeyDown(plus)) - float(ImGui::IsKeyDown(minus));
  };
  const glm::vec3 move(axis(GLFW_KEY_W, GLFW_KEY_S), axis(GLFW_KEY_D, GLFW_KEY_A), 0.0f);
  if (move == glm::vec3(0.0f)) return;
  const Camera& camera = state.session.setup().camera;
  const float speed = glm::length(camera.target - camera.eye) * kFlySpeed;
  state.place_camera(fly(camera, move * speed * io.DeltaTime));
}

void CameraInput::controls(ViewState& state) {
  if (camera_text_of_ != state.session.camera_changes()) {
    camera_text_.set(to_string(state.session.setup().camera));
    camera_text_of_ = state.session.camera_changes();
  }
  camera_text_.input("##camera");
  ImGui::SameLine();
  if (ImGui::Button("set")) {
    try {
      state.place_camera(parse_camera(camera_text_.c_str()));
      state.status.set("");
    } catch (const UsageError& e) {
      state.status.set(std::string("camera: ") + e.what());
    }
  }
  ImGui::Checkbox("fly (W/A/S/D)", &fly_);
  // Wrapped (TextDisabled does not wrap): the panel may be dragged narrow.
  ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyleColorVec4(ImGuiCol_TextDisabled));
  ImGui::TextWrapped("F1 or ?: every mouse and key control");
  ImGui::PopStyleColor();
}

}  // namespace gs::app
