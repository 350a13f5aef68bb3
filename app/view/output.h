// What the viewer writes for scripts and CI: the clicked pixel's walk (--walk-out), the
// window (--screenshot) and the shown frame's figures (--stats).
#pragma once
#include <nlohmann/json.hpp>
#include <string>

namespace gs::gl {
class Window;
}

namespace gs::app {

struct PickedWalk;
struct ViewState;

// The walk as `trace --walk-out` writes it, with the view it was picked in; also that view on
// stdout. InputError when no walk was recorded.
void write_walk(const PickedWalk& picked, const std::string& path);

// The whole window as a PNG. InputError when it is minimised.
void write_screenshot(const gl::Window& window, const std::string& path);

// The shown frame's figures (render --stats's names where they mean the same), the view it
// shows, the last status line, the layout: the viewport's rectangle and, for every ImGui
// window of the last frame, its rectangle, content and visible sizes, scrollbars and whether
// its content is cut off (larger than the visible area on an axis without a scrollbar); and,
// as "compare", the A/B comparison's B (CompareView::stats).
void write_stats(const ViewState& state, const nlohmann::json& compare, const std::string& path);

}  // namespace gs::app
