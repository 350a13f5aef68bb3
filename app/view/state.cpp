#include "app/view/state.h"

#include <algorithm>
#include <cstdio>
#include <utility>

namespace gs::app {

namespace {

// Frames come from recent generations; the bound keeps the map small while the camera moves
// every frame.
constexpr size_t kCamerasKept = 64;

}  // namespace

Session::Session(std::shared_ptr<const Scene> scene, const std::string& accel,
                 const AccelParams& params, std::function<void()> frame_ready)
    : renderer_(std::move(frame_ready)) {
  setup_.scene = std::move(scene);
  setup_.scene_box = setup_.scene->bounds();
  setup_.accel = accel;
  setup_.params = params;
  setup_.max_spp = 256;
}

void Session::move_camera(const Camera& camera) {
  setup_.camera = camera;
  ++camera_changes_;
  restart();
}

void Session::resize(int width, int height) {
  setup_.width = width, setup_.height = height;
  restart();
}

void Session::set_structure(const std::string& accel, const AccelParams& params) {
  setup_.accel = accel;
  setup_.params = params;
  restart();
}

void Session::set_packets(bool packets) {
  setup_.packets = packets;
  restart();
}

void Session::set_max_spp(int max_spp) {
  setup_.max_spp = max_spp;
  restart();
}

void Session::set_scene(std::shared_ptr<const Scene> scene, const Camera& camera) {
  setup_.scene = std::move(scene);
  setup_.scene_box = setup_.scene->bounds();
  setup_.camera = camera;
  ++camera_changes_;
  restart();
}

void Session::restart() {
  if (setup_.width == 0) return;  // not laid out yet: the first resize starts the first pass
  renderer_.restart(setup_);
  ++restarts_;
  cameras_[restarts_] = setup_.camera;
  while (cameras_.size() > kCamerasKept) cameras_.erase(cameras_.begin());
  full_pass_current_ = false;
}

bool Session::take_frame() {
  std::shared_ptr<const ProgressiveFrame> taken =
      renderer_.take_frame(frame_->generation, frame_->pass);
  if (!taken) return false;
  frame_ = std::move(taken);
  const ProgressiveFrame& frame = *frame_;
  const auto camera = cameras_.find(frame.generation);
  frame_camera_ = camera != cameras_.end() ? camera->second : setup_.camera;
  if (frame.generation == restarts_ && frame.pass >= 2 && !full_pass_current_) {
    full_pass_current_ = true;
    full_pass_seconds_.push_back(frame.seconds);
  }
  distances_.clear();
  if (frame.pixels.size() == size_t(frame.width) * size_t(frame.height))
    for (const PixelRecord& p : frame.pixels) distances_.push_back(p.depth);
  return true;
}

void StatusLine::set(const std::string& text) {
  if (!text.empty() && text != text_) std::fprintf(stderr, "gridscope view: %s\n", text.c_str());
  text_ = text;
}

ViewState::ViewState(std::shared_ptr<const Scene> scene, const std::string& accel,
                     const AccelParams& params, const OverlaySelection& overlays,
                     std::function<void()> frame_ready)
    : session(std::move(scene), accel, params, std::move(frame_ready)), overlays(overlays) {}

std::array<int, 2> ViewState::pixel_at(const ImVec2& p) const {
  const ViewSetup& setup = session.setup();
  const int x = std::clamp(int((p.x - viewport.x) * viewport.scale), 0, setup.width - 1);
  const int y = std::clamp(int((p.y - viewport.y) * viewport.scale), 0, setup.height - 1);
  return {x, y};
}

void ViewState::place_camera(const Camera& camera) {
  pivot = camera.target;
  session.move_camera(camera);
}

bool ViewState::structure_ready() {
  if (session.structure_ready()) return true;
  status.set("the structure is still being built: try again in a moment");
  return false;
}

void ViewState::pick(int x, int y) {
  if (!structure_ready()) return;
  const ViewSetup& setup = session.setup();
  picked.walk = session.record_walk(x, y);
  picked.pixel = {x, y};
  picked.size = {setup.width, setup.height};
  picked.camera = setup.camera;
  picked.cell = 0;
  status.set(picked.walk ? "" : "no walk: the structure has no cells");
  if (picked.walk) overlays.walk = true;
  walk_changed();  // stale overlays also show the voxels the walk may have built
}

void ViewState::walk_changed() {
  picked.lines = picked.walk && overlays.walk ? walk_lines(*picked.walk, picked.cell) : LineSet{};
  overlays_stale = true;
}

void ViewState::structure_replaced() {
  picked.walk.reset();
  picked.lines = {};
  picked.cost.reset();
  overlays_stale = true;
}

}  // namespace gs::app
