// The viewer's A/B comparison: a second session, B, renders the main view (A) again with
// another structure or parameter set (a CompareSpec, as `shot --compare` takes it). B
// follows A's camera, size, scene and structure; the viewport shows A and B split at a
// divider, A or B alone (an A/B toggle: key B), or with a heatmap B - A; both heatmaps share
// one scale; the controls section shows the totals side by side.
#pragma once
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "app/compare_spec.h"
#include "app/gl/frame.h"
#include "app/view/state.h"
#include "app/view/text_field.h"
#include "app/view/viewport.h"

namespace gs::app {

class HeatMap;

enum class CompareMode { split, a, b, difference };
// "split", "a", "b", "difference": the script's `set compare-view` words.
const char* compare_mode_name(CompareMode mode);
std::optional<CompareMode> compare_mode_named(const std::string& name);

class CompareView {
 public:
  // `frame_ready` wakes the frame loop when B finishes a pass, as A's renderer does.
  explicit CompareView(std::function<void()> frame_ready);

  // B from A's current view changed by `spec_text` (parse_compare; "off" stops). A bad spec
  // goes to the status line and leaves the comparison as it was.
  void set(ViewState& state, const std::string& spec_text);
  void set_mode(CompareMode mode) { mode_ = mode; }
  bool active() const { return session_ != nullptr; }

  // Each frame, before the viewport is drawn: B follows A and takes its newest frame; with
  // a heatmap, A's range becomes the shared scale.
  void update(ViewState& state, HeatMap& heat_a);
  // After the viewport: B's frame over its part of the viewport, the divider and the labels.
  // True when B's texture was drawn anew (the window must then be drawn again).
  bool draw(const ViewState& state, const HeatMap& heat_a);
  // The controls panel's A/B section.
  void controls(ViewState& state, HeatMap& heat_a);
  // For --stats: null when no comparison runs.
  nlohmann::json stats(const ViewState& state) const;

 private:
  void follow(const ViewState& state);
  void start(ViewState& state);
  // B's frame is of the view A's frame shows: same size and camera.
  bool b_matches_a(const ViewState& state) const;
  // Draws B's part into target_ when what it shows changed (`redrawn`); false when there is
  // none.
  bool refresh_b(const ViewState& state, const HeatMap& heat_a, bool& redrawn);
  // The RGBA image B's part shows for the mode, or empty when there is none to show.
  std::span<const uint8_t> b_image(const ViewState& state, const HeatMap& heat_a);
  void draw_b(const ViewState& state, std::span<const uint8_t> rgba);
  std::string b_label(const ViewState& state) const;
  void stop(HeatMap& heat_a);
  bool spec_controls(ViewState& state);
  void totals_controls(const ViewState& state, const HeatMap& heat_a);

  std::function<void()> frame_ready_;
  std::unique_ptr<Session> session_;  // B
  CompareSpec spec_;
  std::string label_b_;
  std::string a_structure_;  // A's structure and parameters B was derived from
  CompareMode mode_ = CompareMode::split;
  float divider_ = 0.5f;       // where B starts, as a fraction of the viewport's width
  std::vector<float> heat_b_;  // B's heatmap figures per pixel and sample
  // What heat_b_ and target_ were computed from: each is computed again only when its inputs
  // change (a new pass of A or B, another heatmap, range or view), not every UI frame.
  struct HeatInputs {
    uint64_t b_generation = 0;
    int b_pass = 0;
    HeatKind kind = HeatKind::none;
    bool operator==(const HeatInputs&) const = default;
  };
  struct DrawnInputs {
    uint64_t a_generation = 0, b_generation = 0;
    int a_pass = 0, b_pass = 0;
    HeatKind kind = HeatKind::none;
    CompareMode mode = CompareMode::split;
    float heat_hi = 0.0f;
    bool operator==(const DrawnInputs&) const = default;
  };
  std::optional<HeatInputs> heat_b_of_;
  std::optional<DrawnInputs> drawn_of_;
  std::vector<uint8_t> b_rgba_;    // B's heatmap or B - A, when target_ shows one
  float difference_range_ = 0.0f;  // B - A's range, with the heatmaps drawn last
  TextField<160> spec_text_;
  gl::FrameRenderer renderer_;
  ViewportTarget target_;
  bool shown_ = false;         // B's part is drawn
  bool shares_range_ = false;  // A's heat range was set to the shared scale
};

}  // namespace gs::app
