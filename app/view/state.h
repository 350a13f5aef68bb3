// What the viewer's parts share (ViewState): the renderer and the view it is asked for, the
// viewport's place in the window, the camera's pivot and starting view, the picked walk, the
// overlays chosen, and the status line. Each part receives it by reference each frame.
#pragma once
#include <imgui.h>

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "app/view/build_progress.h"
#include "app/view/layout.h"
#include "app/view/picked_walk.h"
#include "core/render/overlay.h"
#include "core/render/progressive.h"

namespace gs::app {

// The renderer and the view it renders. Any change of camera, size, scene or structure
// restarts it (a new generation); a frame it hands back is shown with the camera of its own
// generation, which may be a view already left.
class Session {
 public:
  // `frame_ready` as ProgressiveRenderer takes it.
  Session(std::shared_ptr<const Scene> scene, const std::string& accel, const AccelParams& params,
          std::function<void()> frame_ready = {});

  const ViewSetup& setup() const { return setup_; }
  // Each restarts the renderer, once the viewport has a size (see resize).
  void move_camera(const Camera& camera);
  void resize(int width, int height);
  void set_structure(const std::string& accel, const AccelParams& params);
  // Primary and shadow rays by packets or one at a time: the passes restart on the same
  // structure.
  void set_packets(bool packets);
  // Accumulation stops at this many samples per pixel (ViewSetup::max_spp).
  void set_max_spp(int max_spp);
  void set_scene(std::shared_ptr<const Scene> scene, const Camera& camera);

  // Takes the renderer's newest frame if it is newer than the one shown; true then.
  bool take_frame();
  const ProgressiveFrame& frame() const { return *frame_; }
  const Camera& frame_camera() const { return frame_camera_; }
  // The frame's per-pixel distances (empty without per-pixel records), for depth-testing lines.
  const std::vector<float>& distances() const { return distances_; }
  // The current view's full-resolution pass (or a later one) is shown.
  bool full_pass_current() const { return full_pass_current_; }
  // For each view whose full-resolution pass was shown: seconds from its restart to that
  // pass (ProgressiveFrame::seconds), in order. The first includes the structure's build.
  const std::vector<double>& full_pass_seconds() const { return full_pass_seconds_; }
  // The frame shown is of the current view and has a pass.
  bool frame_current() const { return frame_->generation == restarts_ && frame_->pass > 0; }
  // False until the first restart (a window minimised since its first frame never starts).
  bool started() const { return restarts_ > 0; }
  // Counts camera changes: a text field showing the camera refreshes when it moves.
  uint64_t camera_changes() const { return camera_changes_; }

  bool structure_ready() const { return renderer_.structure_ready(); }
  BuildStatus build_status() const { return renderer_.build_status(); }
  std::optional<Walk> record_walk(int x, int y) { return renderer_.record_walk(x, y); }
  void with_structure_paused(const std::function<void(const Accelerator&)>& visit) {
    renderer_.with_structure_paused(visit);
  }

 private:
  void restart();

  ViewSetup setup_;
  ProgressiveRenderer renderer_;  // its destructor stops the workers
  uint64_t restarts_ = 0;
  std::map<uint64_t, Camera> cameras_;  // the camera of each recent generation, for its frames
  uint64_t camera_changes_ = 0;
  std::shared_ptr<const ProgressiveFrame> frame_ = std::make_shared<const ProgressiveFrame>();
  Camera frame_camera_;
  std::vector<float> distances_;
  bool full_pass_current_ = false;
  std::vector<double> full_pass_seconds_;
};

// Where the image sits in the window, in window units (ImGui's), and the framebuffer's
// pixels per unit.
struct Viewport {
  float x = 0, y = 0, w = kMinViewport, h = kMinViewport;
  float scale = 1.0f;
  bool contains(const ImVec2& p) const {
    return p.x >= x && p.y >= y && p.x < x + w && p.y < y + h;
  }
};

// The controls panel's status line; also on stderr, so that logs and scripts see it.
class StatusLine {
 public:
  void set(const std::string& text);
  const std::string& text() const { return text_; }

 private:
  std::string text_;
};

struct ViewState {
  ViewState(std::shared_ptr<const Scene> scene, const std::string& accel, const AccelParams& params,
            const OverlaySelection& overlays, std::function<void()> frame_ready = {});

  // The viewport pixel under a window point (render pixels, top-left origin).
  std::array<int, 2> pixel_at(const ImVec2& p) const;
  // A camera chosen outright (framing, reset, typed, flown, a new pivot): its target becomes
  // the pivot.
  void place_camera(const Camera& camera);
  // record_walk waits for the structure: refused while it is built, so the UI never freezes.
  bool structure_ready();
  // A click: that pixel's walk, by the traversal that renders, shown and inspected.
  void pick(int x, int y);
  // Another walk, cell or walk overlay choice: the walk's lines again, the cost read anew.
  void walk_changed();
  // A new structure (scene, structure or parameters): the old walk describes another one.
  void structure_replaced();

  Session session;
  Viewport viewport;
  std::optional<Camera> start_camera;  // R returns here; set once laid out, and per scene
  glm::vec3 pivot{0.0f};               // orbiting turns about it
  PickedWalk picked;
  OverlaySelection overlays;    // what is drawn: the checkboxes and the heatmap
  bool colour_by_axis = false;  // cells coloured by cut axis instead of depth
  bool overlays_stale = true;   // the overlay cache reads the structure again at once
  // A/B: B has not yet shown a full-resolution pass of the current view (scripts wait).
  bool compare_pending = false;
  StatusLine status;
  BuildBarRecord build_bar;  // what the build progress bar has shown
  // UI frames built, and those of them drawn: a frame that would look as the window already
  // does is not drawn (Viewer::draw_frame).
  uint64_t frames_built = 0, frames_drawn = 0;
};

}  // namespace gs::app
