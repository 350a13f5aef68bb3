#include "app/view/splitters.h"

#include <algorithm>
#include <initializer_list>

namespace gs::app {

WindowLayout Splitters::lay_out(const ImVec2& display) {
  for (const Splitter which : {Splitter::right, Splitter::bottom}) {
    if (asked_[int(which)] == 0.0f) continue;
    move(which, asked_[int(which)], lay_out_window(display.x, display.y, positions_));
    asked_[int(which)] = 0.0f;
  }
  return lay_out_window(display.x, display.y, positions_);
}

void Splitters::draw(const WindowLayout& layout) {
  bar("##right splitter", layout.right_splitter, Splitter::right, layout);
  bar("##bottom splitter", layout.bottom_splitter, Splitter::bottom, layout);
}

void Splitters::move(Splitter which, float pixels, const WindowLayout& layout) {
  // The panel on the far side of the bar gives up what the viewport gains, down to its
  // minimum (a size of 0 would mean "not dragged").
  if (which == Splitter::right)
    positions_.controls_width = std::max(layout.controls.w - pixels, kControlsMinWidth);
  else
    positions_.bottom_height = std::max(layout.bottom.h - pixels, kBottomMinHeight);
}

void Splitters::bar(const char* name, const Rect& rect, Splitter which,
                    const WindowLayout& layout) {
  ImGui::SetNextWindowPos(ImVec2(rect.x, rect.y));
  ImGui::SetNextWindowSize(ImVec2(rect.w, rect.h));
  // Windows are at least WindowMinSize (32x32) unless told otherwise; a bar is thinner.
  ImGui::PushStyleVar(ImGuiStyleVar_WindowMinSize, ImVec2(1, 1));
  ImGui::PushStyleVar(ImGuiStyleVar_WindowPadding, ImVec2(0, 0));
  ImGui::PushStyleVar(ImGuiStyleVar_WindowBorderSize, 0.0f);
  ImGui::Begin(name, nullptr,
               ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoMove |
                   ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoBackground);
  ImGui::InvisibleButton("bar", ImVec2(rect.w, rect.h));
  const bool active = ImGui::IsItemActive(), hovered = ImGui::IsItemHovered();
  const ImGuiCol colour = active    ? ImGuiCol_SeparatorActive
                          : hovered ? ImGuiCol_SeparatorHovered
                                    : ImGuiCol_Separator;
  ImGui::GetWindowDrawList()->AddRectFilled(
      ImVec2(rect.x, rect.y), ImVec2(rect.right(), rect.bottom()), ImGui::GetColorU32(colour));
  if (active || hovered)
    ImGui::SetMouseCursor(which == Splitter::right ? ImGuiMouseCursor_ResizeEW
                                                   : ImGuiMouseCursor_ResizeNS);
  const ImVec2 delta = ImGui::GetIO().MouseDelta;
  const float moved = which == Splitter::right ? delta.x : delta.y;
  if (active && moved != 0.0f) move(which, moved, layout);
  ImGui::End();
  ImGui::PopStyleVar(3);
}

}  // namespace gs::app
