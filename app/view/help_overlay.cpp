#include "app/view/help_overlay.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>

#include <algorithm>
#include <span>

#include "app/view/camera_input.h"

namespace gs::app {

namespace {

// The controls of the viewer's other parts; the camera's are camera_controls().
constexpr ControlHelp kViewerControls[] = {
    {"F1 or ?", "show or hide this help"},
    {"drag a bar between panels", "resize the viewport and the panels (the render restarts)"},
    {"click a walk step or table row", "inspect that cell: highlight and cost report"},
    {"click a table header", "sort the states table by that column"},
    {"B", "while comparing (A/B section): show A or B alone, in turn"},
    {"Ctrl+click a slider", "type its value"},
    {"hover a slider or a cut cell", "its meaning or full text"},
};

bool help_key_pressed() {
  const ImGuiIO& io = ImGui::GetIO();
  if (io.WantCaptureKeyboard) return false;  // typing into a text field
  if (ImGui::IsKeyPressed(GLFW_KEY_F1, false)) return true;
  return std::find(io.InputQueueCharacters.begin(), io.InputQueueCharacters.end(), '?') !=
         io.InputQueueCharacters.end();
}

void control_rows(const char* group, std::span<const ControlHelp> controls) {
  ImGui::TableNextRow();
  ImGui::TableNextColumn();
  ImGui::TextDisabled("%s", group);
  for (const ControlHelp& control : controls) {
    ImGui::TableNextRow();
    ImGui::TableNextColumn();
    ImGui::TextUnformatted(control.input);
    ImGui::TableNextColumn();
    ImGui::TextUnformatted(control.action);
  }
}

}  // namespace

void HelpOverlay::draw() {
  if (help_key_pressed()) toggle();
  const bool opening = shown_ && !was_shown_;
  was_shown_ = shown_;
  if (!shown_) return;
  if (opening) ImGui::SetNextWindowFocus();  // over the panels as it opens
  const ImVec2 display = ImGui::GetIO().DisplaySize;
  ImGui::SetNextWindowPos(ImVec2(display.x * 0.5f, display.y * 0.5f), ImGuiCond_Always,
                          ImVec2(0.5f, 0.5f));
  if (ImGui::Begin("mouse and keyboard", &shown_,
                   ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoCollapse |
                       ImGuiWindowFlags_NoSavedSettings) &&
      ImGui::BeginTable("controls", 2, ImGuiTableFlags_RowBg | ImGuiTableFlags_SizingFixedFit)) {
    control_rows("camera and image", camera_controls());
    control_rows("panels", kViewerControls);
    ImGui::EndTable();
  }
  ImGui::End();
}

}  // namespace gs::app
