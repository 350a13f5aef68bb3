#include "app/view.h"

#include "core/base/files.h"
#include "core/base/timing.h"

// glad first: it claims the GL header guard before GLFW or ImGui could pull in GL headers.
#include <glad/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <glm/geometric.hpp>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>

#include "app/flags.h"
#include "app/gl/frame.h"
#include "app/gl/imgui_renderer.h"
#include "app/gl/window.h"
#include "core/accel/grid1d/cost_model.h"
#include "core/accel/grid1d/grid1d.h"
#include "core/base/error.h"
#include "core/geometry/ray_io.h"
#include "core/render/camera_control.h"
#include "core/render/overlay.h"
#include "core/render/progressive.h"
#include "core/render/render.h"
#include "core/trace/trace_job.h"

namespace gs::app {

namespace {

constexpr const char* kDefaultScene = "builtin:lumpy";
// The close-up of lumpy's cluster the README's pictures use.
constexpr const char* kCloseUp = "eye=3.2,-4.2,2.2;target=0,0,0.35;up=0,0,1;fov=40";
// Panels take a share of the window within these bounds; the viewport gets the rest.
constexpr float kPanelShare = 0.3f, kPanelMin = 300.0f, kPanelMax = 420.0f;  // on the right
constexpr float kBottomShare = 0.3f, kBottomMin = 180.0f, kBottomMax = 300.0f;
constexpr float kMinViewport = 16.0f;  // the viewport never shrinks below this
// ... nor grows beyond this many pixels a side, whatever the window: the renderer and the UI
// hold about 90 bytes per pixel in flight (images, per-pixel records, sums), 1.5 GB here.
constexpr int kMaxViewportSide = 4096;
constexpr double kOverlayInterval = 0.3;  // seconds between overlay refreshes while building
constexpr float kOrbitSpeed = 0.006f;     // radians per pixel dragged
constexpr float kDollyStep = 0.9f;        // distance kept per wheel notch
constexpr float kFlySpeed = 0.8f;         // eye-to-target distances per second
constexpr double kIdleWait = 0.05;        // seconds a minimised window sleeps per frame

// A scripted click is followed by this many frames before exiting, so that tables that
// size themselves from their content have measured it when the screenshot is taken.
constexpr int kFramesAfterClick = 2;

const char* const kHeatNames[] = {"none", "steps", "tests", "built"};
const ImVec4 kWarning(1.0f, 0.4f, 0.4f, 1.0f);  // errors and figures that need attention

struct Rect {
  float x = 0, y = 0, w = kMinViewport, h = kMinViewport;
  bool contains(const ImVec2& p) const {
    return p.x >= x && p.y >= y && p.x < x + w && p.y < y + h;
  }
};

// The viewport's own framebuffer. FrameRenderer draws at (0, 0) of the current framebuffer
// and its image shader maps gl_FragCoord to texels, so the frame is drawn here and shown in
// the window as an image under the panels.
class Target {
 public:
  ~Target() { release(); }
  void resize(int width, int height) {
    if (width == width_ && height == height_) return;
    release();
    width_ = width, height_ = height;
    glGenTextures(1, &colour_);
    glBindTexture(GL_TEXTURE_2D, colour_);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, width, height, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glGenRenderbuffers(1, &depth_);
    glBindRenderbuffer(GL_RENDERBUFFER, depth_);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width, height);
    glGenFramebuffers(1, &fbo_);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, colour_, 0);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
  }
  void bind() const { glBindFramebuffer(GL_FRAMEBUFFER, fbo_); }
  ImTextureID texture() const { return reinterpret_cast<ImTextureID>(intptr_t(colour_)); }

 private:
  void release() {
    if (fbo_) glDeleteFramebuffers(1, &fbo_);
    if (depth_) glDeleteRenderbuffers(1, &depth_);
    if (colour_) glDeleteTextures(1, &colour_);
    fbo_ = depth_ = colour_ = 0;
  }
  unsigned fbo_ = 0, colour_ = 0, depth_ = 0;
  int width_ = 0, height_ = 0;
};

// The voxel (by depth) the walk had gone down through when it reached cell `upto`: a
// descent rewrites its level and every deeper one, a step within an array keeps them.
std::optional<uint32_t> parent_voxel(const Walk& walk, size_t upto) {
  std::vector<uint32_t> path;  // path[d]: the subdivided voxel at depth d
  for (size_t i = 0; i <= upto && i < walk.cells.size(); ++i)
    for (const WalkDescent& d : walk.cells[i].descents) {
      path.resize(std::max<size_t>(path.size(), d.depth + 1), Grid1D::kNone);
      path[d.depth] = d.voxel;
      path.resize(d.depth + 1);
    }
  const uint32_t depth = walk.cells[upto].depth;
  if (depth == 0 || path.size() < depth || path[depth - 1] == Grid1D::kNone) return std::nullopt;
  return path[depth - 1];
}

// What the walk did inside `voxel`: the cells it visited there, tests and rejections.
struct RayInVoxel {
  int cells = 0;
  uint64_t tests = 0, rejections = 0;
};
RayInVoxel ray_in_voxel(const Walk& walk, uint32_t voxel) {
  RayInVoxel here;
  for (size_t i = 0; i < walk.cells.size(); ++i) {
    if (parent_voxel(walk, i) != std::optional<uint32_t>(voxel)) continue;
    ++here.cells;
    here.tests += walk.cells[i].tests;
    here.rejections += walk.cells[i].rejections;
  }
  return here;
}

std::string descents_text(const WalkCell& cell) {
  static const char* const kCase[] = {"reused", "index_only", "reinitialised"};
  std::string text;
  for (const WalkDescent& d : cell.descents) {
    char part[160];
    std::snprintf(part, sizeof part, "%s%c g%u G%llu s%u c%lld %s", text.empty() ? "" : "; ",
                  "xyz"[d.axis % 3], d.granularity, (unsigned long long)d.absolute_granularity,
                  d.state, (long long)d.cell, kCase[int(d.state_case)]);
    text += part;
  }
  return text.empty() ? "-" : text;
}

std::string optional_figure(const std::optional<uint64_t>& value) {
  return value ? std::to_string(*value) : std::string("n/a");
}

void copy_text(char* buffer, size_t size, const std::string& text) {
  std::snprintf(buffer, size, "%s", text.c_str());
}

// A byte count as --memory-budget takes it back: the largest suffix that divides it.
std::string byte_text(uint64_t bytes) {
  constexpr std::pair<int, const char*> kSuffixes[] = {{30, "G"}, {20, "M"}, {10, "K"}};
  for (const auto& [shift, suffix] : kSuffixes)
    if (bytes > 0 && bytes % (uint64_t{1} << shift) == 0)
      return std::to_string(bytes >> shift) + suffix;
  return std::to_string(bytes);
}

nlohmann::json optional_json(const std::optional<uint64_t>& value) {
  return value ? nlohmann::json(*value) : nlohmann::json(nullptr);
}

class Viewer {
 public:
  Viewer(const ViewJob& job, std::shared_ptr<const Scene> scene, std::vector<ScriptStep> steps)
      : job_(job),
        window_(job.width, job.height, "gridscope view"),
        scene_(std::move(scene)),
        steps_(std::move(steps)) {
    setup_.scene = scene_;
    setup_.accel = job.accel;
    setup_.params = job.params;
    setup_.max_spp = 256;
    edit_params_ = job.params;
    copy_text(budget_text_, sizeof budget_text_, byte_text(job.params.memory_budget));
    const std::vector<std::string> names = accelerator_names();
    edit_accel_ = int(std::find(names.begin(), names.end(), job.accel) - names.begin());
    copy_text(scene_path_, sizeof scene_path_, scene_->name);
    show_cells_ = job.overlays.cells, show_states_ = job.overlays.states;
    show_walk_ = job.overlays.walk, heat_ = job.overlays.heat;
    if (job.frames > 0 || !steps_.empty()) glfwSwapInterval(0);  // scripts need no vsync
    // The viewport is a texture and a depth renderbuffer: no larger than GL allows either.
    GLint texture = 0, renderbuffer = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &texture);
    glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &renderbuffer);
    max_viewport_side_ = std::min({kMaxViewportSide, int(texture), int(renderbuffer)});
  }

  // One frame per turn. A minimised window draws nothing (no 0x0 viewport, texture or
  // render) but still counts frames, runs script steps and takes loads and passes.
  void run() {
    while (!window_.should_close()) {
      window_.poll_events();
      run_steps();
      take_loaded_scene();
      update_frame();
      const bool drawn = !window_.minimised();
      if (drawn)
        draw_frame();
      else
        window_.wait_events(kIdleWait);
      ++frames_done_;
      if (script_done()) {
        if (!job_.screenshot.empty()) screenshot();
        break;
      }
      if (drawn) window_.swap();
    }
    window_.hide();  // gone at once, while the workers finish their rows
    if (!job_.stats.empty()) write_stats();
  }

 private:
  // --- one UI frame ----------------------------------------------------------------
  void draw_frame() {
    window_.begin_frame();
    ImGui::NewFrame();
    step();
    ImGui::Render();
    draw();
  }

  void step() {
    layout();
    if (job_.frames > 0) run_click();
    handle_mouse();
    handle_keys();
    refresh_overlays(false);
    draw_viewport();
    controls_panel();
    bottom_panel();
  }

  // Places the viewport and panels for the window's current size (no docking in 1.86);
  // a new viewport size restarts the renderer at that size.
  void layout() {
    const ImGuiIO& io = ImGui::GetIO();
    scale_ = std::max(io.DisplayFramebufferScale.x, 1.0f);
    view_.x = view_.y = 0;
    const float panel = std::clamp(io.DisplaySize.x * kPanelShare, kPanelMin, kPanelMax);
    const float bottom = std::clamp(io.DisplaySize.y * kBottomShare, kBottomMin, kBottomMax);
    const float largest = float(max_viewport_side_) / scale_;
    view_.w = std::clamp(io.DisplaySize.x - panel, kMinViewport, largest);
    view_.h = std::clamp(io.DisplaySize.y - bottom, kMinViewport, largest);
    const int width = int(view_.w * scale_), height = int(view_.h * scale_);
    if (width == setup_.width && height == setup_.height) return;
    setup_.width = width, setup_.height = height;
    if (!start_camera_) {
      start_camera_ = initial_camera();
      setup_.camera = *start_camera_;
      pivot_ = setup_.camera.target;
      copy_text(camera_text_, sizeof camera_text_, to_string(setup_.camera));
    }
    restart();
  }

  Camera initial_camera() const {
    if (job_.camera) return *job_.camera;
    if (job_.scene.empty()) return parse_camera(kCloseUp);
    return frame_box(scene_->bounds(), float(setup_.width) / float(setup_.height));
  }

  void restart() {
    if (setup_.width == 0) return;  // not laid out yet: layout() starts the first pass
    renderer_.restart(setup_);
    ++restarts_;
    cameras_[restarts_] = setup_.camera;
    while (cameras_.size() > 64) cameras_.erase(cameras_.begin());
    full_pass_current_ = false;
  }

  void move_camera(const Camera& camera) {
    setup_.camera = camera;
    copy_text(camera_text_, sizeof camera_text_, to_string(camera));
    restart();
  }

  // A new structure (scene, structure or parameters): the old walk describes another one.
  void restart_structure() {
    walk_.reset();
    walk_lines_ = {};
    cost_.reset();
    overlays_dirty_ = true;
    restart();
  }

  void update_frame() {
    std::optional<ProgressiveFrame> frame = renderer_.take_frame(frame_.generation, frame_.pass);
    if (!frame) return;
    frame_ = std::move(*frame);
    const auto camera = cameras_.find(frame_.generation);
    frame_camera_ = camera != cameras_.end() ? camera->second : setup_.camera;
    if (frame_.generation == restarts_ && frame_.pass >= 2) full_pass_current_ = true;
    distances_.clear();
    if (frame_.pixels.size() == size_t(frame_.width) * size_t(frame_.height))
      for (const PixelRecord& p : frame_.pixels) distances_.push_back(p.depth);
    heat_dirty_ = true;
    if (!frame_.error.empty() && job_.frames > 0)
      throw InputError("view: rendering failed: " + frame_.error);
  }

  // --- script mode (--frames, --click, --walk-out, --screenshot, --script, --stats) -------
  // The steps due by this frame, in order.
  void run_steps() {
    while (next_step_ < steps_.size() && steps_[next_step_].frame <= frames_done_ + 1)
      run_step(steps_[next_step_++]);
  }

  void run_step(const ScriptStep& step) {
    switch (step.action) {
      case ScriptStep::Action::resize:
        window_.resize(step.size[0], step.size[1]);
        break;
      case ScriptStep::Action::open:
        open_scene(step.name);
        break;
      case ScriptStep::Action::set:
        set_parameter(step.name, step.value);
        break;
      case ScriptStep::Action::close:
        window_.close();
        break;
    }
  }

  // A checked step (parse_script): the edit fields take the value, then Apply.
  void set_parameter(const std::string& name, const std::string& value) {
    if (name == "accel") {
      const std::vector<std::string> names = accelerator_names();
      edit_accel_ = int(std::find(names.begin(), names.end(), value) - names.begin());
    } else {
      apply_structure_flag(edit_params_, "--" + name, value);
      copy_text(budget_text_, sizeof budget_text_, byte_text(edit_params_.memory_budget));
    }
    apply_structure();
  }

  void run_click() {
    if (!job_.click || click_done_ || !full_pass_current_) return;
    const auto [fx, fy] = *job_.click;
    const int x = std::min(int(fx * setup_.width), setup_.width - 1);
    const int y = std::min(int(fy * setup_.height), setup_.height - 1);
    pick(x, y);
    click_done_ = true;
    click_frame_ = frames_done_;
    if (!job_.walk_out.empty()) write_walk();
  }

  // Every step run, no load pending, and the current view's full-resolution pass shown (or
  // no view at all: minimised since the first frame).
  bool script_done() const {
    return job_.frames > 0 && frames_done_ >= job_.frames &&
           (full_pass_current_ || restarts_ == 0) && next_step_ == steps_.size() &&
           !loader_.pending() &&
           (!job_.click || (click_done_ && frames_done_ > click_frame_ + kFramesAfterClick));
  }

  void write_walk() const {
    if (!walk_)
      throw InputError("view: pixel " + std::to_string(walk_pixel_[0]) + "," +
                       std::to_string(walk_pixel_[1]) + ": no walk recorded");
    nlohmann::json json = to_json(*walk_);
    const std::string camera = to_string(walk_camera_);
    json["view"] = {{"width", walk_size_[0]},
                    {"height", walk_size_[1]},
                    {"camera", camera},
                    {"pixel", {walk_pixel_[0], walk_pixel_[1]}}};
    write_json(job_.walk_out, json);
    std::printf("viewport %dx%d camera %s pixel %d,%d\n", walk_size_[0], walk_size_[1],
                camera.c_str(), walk_pixel_[0], walk_pixel_[1]);
  }

  void screenshot() const {
    if (window_.minimised()) throw InputError(job_.screenshot + ": the window is minimised");
    const glm::ivec2 size = window_.framebuffer_size();
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glReadBuffer(GL_BACK);
    std::vector<uint8_t> rgba = gl::read_pixels(size.x, size.y);  // rows flipped to the top
    for (size_t i = 3; i < rgba.size(); i += 4) rgba[i] = 255;    // the window is opaque
    write_png(job_.screenshot, size.x, size.y, rgba);
  }

  // The shown frame's figures (render --stats's names where they mean the same), the view
  // it shows, and the last status line.
  void write_stats() const {
    const StructureStats& s = frame_.structure;
    const nlohmann::json stats = {
        {"scene", scene_->name},
        {"accel", setup_.accel},
        {"parameters", setup_.params.to_json()},
        {"triangles", scene_->triangle_count()},
        {"view",
         {{"width", frame_.width},
          {"height", frame_.height},
          {"camera", to_string(frame_camera_)},
          {"pass", frame_.pass},
          {"spp", frame_.spp},
          {"current", frame_.generation == restarts_ && frame_.pass > 0}}},
        {"rays", frame_.rays},
        {"rays_per_second", frame_.rays_per_second},
        {"build_seconds", s.build_seconds},
        {"nodes", optional_json(s.nodes)},
        {"voxels_subdivided", optional_json(s.voxels_subdivided)},
        {"leaves", optional_json(s.leaves)},
        {"traversal_states", optional_json(s.traversal_states)},
        {"memory_bytes", s.memory_bytes},
        {"voxels_over_budget", s.voxels_over_budget},
        {"error", frame_.error},
        {"status", status_}};
    write_json(job_.stats, stats);
  }

  // The panel's status line; also on stderr, so that logs and scripts see it.
  void set_status(const std::string& text) {
    if (!text.empty() && text != status_)
      std::fprintf(stderr, "gridscope view: %s\n", text.c_str());
    status_ = text;
  }

  // --- picking and camera --------------------------------------------------------------
  // The viewport pixel under a window point (render pixels, top-left origin).
  std::array<int, 2> pixel_at(const ImVec2& p) const {
    const int x = std::clamp(int((p.x - view_.x) * scale_), 0, setup_.width - 1);
    const int y = std::clamp(int((p.y - view_.y) * scale_), 0, setup_.height - 1);
    return {x, y};
  }

  // record_walk waits for the structure: refused while it is built, so the UI never freezes.
  bool structure_ready() {
    if (renderer_.structure_ready()) return true;
    set_status("the structure is still being built: try again in a moment");
    return false;
  }

  // A click: that pixel's walk, by the traversal that renders, shown and inspected.
  void pick(int x, int y) {
    if (!structure_ready()) return;
    walk_ = renderer_.record_walk(x, y);
    walk_pixel_ = {x, y};
    walk_size_ = {setup_.width, setup_.height};
    walk_camera_ = setup_.camera;
    walk_cell_ = 0;
    set_status(walk_ ? "" : "no walk: the structure has no cells");
    if (walk_) show_walk_ = true;
    walk_changed();
    overlays_dirty_ = true;  // the walk may have built voxels
  }

  void walk_changed() {
    walk_lines_ = walk_ && show_walk_ ? walk_lines(*walk_, walk_cell_) : LineSet{};
    cost_dirty_ = true;
  }

  // Double-click: the pivot (and target) moves to the surface under the cursor.
  void set_pivot_at(int x, int y) {
    if (!structure_ready()) return;
    const std::optional<Walk> walk = renderer_.record_walk(x, y);
    if (!walk || !walk->hit.found()) {
      set_status(walk ? "pivot: nothing under the cursor" : "pivot: needs a structure with cells");
      return;
    }
    const glm::vec3 point = walk->ray.origin + walk->hit.t * walk->ray.dir;
    pivot_ = point;
    Camera camera = setup_.camera;
    camera.target = point;
    move_camera(camera);
  }

  void handle_mouse() {
    const ImGuiIO& io = ImGui::GetIO();
    const bool over = view_.contains(io.MousePos) && !io.WantCaptureMouse;
    if (over && ImGui::IsMouseDoubleClicked(0)) {
      const auto [x, y] = pixel_at(io.MousePos);
      set_pivot_at(x, y);
      skip_release_ = true;
    } else if (over && (ImGui::IsMouseClicked(0) || ImGui::IsMouseClicked(2))) {
      dragging_ = ImGui::IsMouseClicked(2) ? 2 : 0;
      drag_active_ = true;
    }
    if (drag_active_) drag(io);
    if (over && io.MouseWheel != 0.0f)
      move_camera(dolly(setup_.camera, 1.0f - std::pow(kDollyStep, io.MouseWheel)));
  }

  void drag(const ImGuiIO& io) {
    const ImVec2 d = io.MouseDelta;
    drag_moved_ = drag_moved_ || ImGui::IsMouseDragging(dragging_);
    if ((d.x != 0.0f || d.y != 0.0f) && drag_moved_) {
      if (dragging_ == 0 && !io.KeyShift)
        move_camera(orbit(setup_.camera, pivot_, -d.x * kOrbitSpeed, -d.y * kOrbitSpeed));
      else
        // camera_control's pan moves the view by minus the drag, y up: the scene follows.
        move_camera(pan(setup_.camera, -d.x / view_.h, d.y / view_.h));
    }
    if (!ImGui::IsMouseReleased(dragging_)) return;
    // A press and release without a drag is a click: pick that pixel's walk.
    if (dragging_ == 0 && !skip_release_ && !drag_moved_ && view_.contains(io.MousePos)) {
      const auto [x, y] = pixel_at(io.MousePos);
      pick(x, y);
    }
    drag_active_ = skip_release_ = drag_moved_ = false;
  }

  void handle_keys() {
    const ImGuiIO& io = ImGui::GetIO();
    if (io.WantCaptureKeyboard) return;
    if (ImGui::IsKeyPressed(GLFW_KEY_F, false)) {
      const Camera framed = frame_box(scene_->bounds(), float(setup_.width) / setup_.height);
      pivot_ = framed.target;
      move_camera(framed);
    }
    if (ImGui::IsKeyPressed(GLFW_KEY_R, false) && start_camera_) {
      pivot_ = start_camera_->target;
      move_camera(*start_camera_);
    }
    if (fly_) fly_keys(io);
  }

  void fly_keys(const ImGuiIO& io) {
    const auto axis = [](int plus, int minus) {
      return float(ImGui::IsKeyDown(plus)) - float(ImGui::IsKeyDown(minus));
    };
    const glm::vec3 move(axis(GLFW_KEY_W, GLFW_KEY_S), axis(GLFW_KEY_D, GLFW_KEY_A), 0.0f);
    if (move == glm::vec3(0.0f)) return;
    const float speed = glm::length(setup_.camera.target - setup_.camera.eye) * kFlySpeed;
    move_camera(fly(setup_.camera, move * speed * io.DeltaTime));
    pivot_ = setup_.camera.target;
  }

  // --- overlays ------------------------------------------------------------------------
  // Overlays read the structure while workers are paused, so they are refreshed a few
  // times a second while it grows, and at once when toggled or picked.
  void refresh_overlays(bool force) {
    const double since = seconds_since(overlay_time_);
    const bool grown = frame_.structure.nodes.value_or(0) != overlay_nodes_;
    if (!force && !overlays_dirty_ && !cost_dirty_ && !(grown && since >= kOverlayInterval)) return;
    overlay_time_ = Clock::now();
    overlay_nodes_ = frame_.structure.nodes.value_or(0);
    renderer_.with_structure_paused([this](const Accelerator& accel) { read_structure(accel); });
    overlays_dirty_ = cost_dirty_ = false;
  }

  void read_structure(const Accelerator& accel) {
    structure_lines_.clear();
    states_.clear();
    cost_.reset();
    const Grid1D* grid = accel.grid1d();
    nodes_built_ = grid ? grid->voxel_count() : 0;
    if (!grid) return;
    if (show_cells_)
      structure_lines_.push_back(
          cell_lines(*grid, colour_by_axis_ ? CellColoring::axis : CellColoring::depth));
    if (show_states_) structure_lines_.push_back(state_lines(*grid));
    states_ = state_table(*grid);
    if (walk_ && !walk_->cells.empty())
      if (const std::optional<uint32_t> parent = parent_voxel(*walk_, size_t(walk_cell_)))
        cost_ = grid->cost_report(*parent), ray_here_ = ray_in_voxel(*walk_, *parent);
  }

  const std::vector<uint8_t>& heat_rgba() {
    if (!heat_dirty_) return heat_rgba_;
    heat_dirty_ = false;
    heat_values_ = heat_values(frame_.pixels, heat_, frame_.spp);
    heat_max_ =
        heat_values_.empty() ? 0.0f : *std::max_element(heat_values_.begin(), heat_values_.end());
    if (heat_auto_) heat_lo_ = 0.0f, heat_hi_ = std::max(heat_max_, 1.0f);
    heat_rgba_ = heat_image(heat_values_, heat_lo_, std::max(heat_hi_, heat_lo_ + 1e-6f));
    return heat_rgba_;
  }

  // --- drawing -------------------------------------------------------------------------
  void draw_viewport() {
    target_.resize(setup_.width, setup_.height);
    target_.bind();
    const size_t pixels = size_t(frame_.width) * size_t(frame_.height);
    if (frame_.image.rgba.size() == pixels * 4 && pixels > 0) {
      std::vector<LineSet> lines = structure_lines_;
      if (show_walk_ && !walk_lines_.vertices.empty()) lines.push_back(walk_lines_);
      const bool heat = heat_ != HeatKind::none && frame_.pixels.size() == pixels;
      gl::FrameInput input;
      input.image_width = frame_.width;
      input.image_height = frame_.height;
      input.rgba = heat ? std::span<const uint8_t>(heat_rgba()) : frame_.image.rgba;
      input.distance = distances_;
      input.camera = frame_camera_;
      input.scene_box = scene_->bounds();
      input.lines = lines;
      frame_renderer_.draw(setup_.width, setup_.height, input);
    } else {
      glViewport(0, 0, setup_.width, setup_.height);
      glClearColor(kBackground[0] / 255.0f, kBackground[1] / 255.0f, kBackground[2] / 255.0f, 1);
      glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    // GL textures count rows from the bottom: flip v.
    ImGui::GetBackgroundDrawList()->AddImage(target_.texture(), ImVec2(view_.x, view_.y),
                                             ImVec2(view_.x + view_.w, view_.y + view_.h),
                                             ImVec2(0, 1), ImVec2(1, 0));
  }

  void draw() {
    const glm::ivec2 size = window_.framebuffer_size();
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, size.x, size.y);
    glClearColor(0.1f, 0.1f, 0.12f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    imgui_renderer_.draw(ImGui::GetDrawData());
  }

  // --- panels ----------------------------------------------------------------------------
  static void place(float x, float y, float w, float h) {
    ImGui::SetNextWindowPos(ImVec2(x, y));
    ImGui::SetNextWindowSize(ImVec2(w, h));
  }
  static constexpr ImGuiWindowFlags kPanelFlags =
      ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse |
      ImGuiWindowFlags_NoSavedSettings;

  void controls_panel() {
    const ImVec2 display = ImGui::GetIO().DisplaySize;
    place(view_.w, 0, std::max(display.x - view_.w, 1.0f), display.y);
    ImGui::Begin("controls", nullptr, kPanelFlags);
    if (ImGui::CollapsingHeader("structure", ImGuiTreeNodeFlags_DefaultOpen)) structure_controls();
    if (ImGui::CollapsingHeader("overlays", ImGuiTreeNodeFlags_DefaultOpen)) overlay_controls();
    if (ImGui::CollapsingHeader("camera", ImGuiTreeNodeFlags_DefaultOpen)) camera_controls();
    if (ImGui::CollapsingHeader("scene", ImGuiTreeNodeFlags_DefaultOpen)) scene_controls();
    if (!status_.empty()) ImGui::TextWrapped("%s", status_.c_str());
    ImGui::End();
  }

  void structure_controls() {
    const std::vector<std::string> names = accelerator_names();
    for (int i = 0; i < int(names.size()); ++i) {
      if (i) ImGui::SameLine();
      ImGui::RadioButton(names[size_t(i)].c_str(), &edit_accel_, i);
    }
    const auto cost = [](const char* label, double& value) {
      const double lo = 0.0, hi = 20.0;
      ImGui::SliderScalar(label, ImGuiDataType_Double, &value, &lo, &hi, "%.2f");
    };
    cost("Intcost", edit_params_.intcost);
    cost("Repcost", edit_params_.repcost);
    cost("Travcost", edit_params_.travcost);
    cost("Vertcost", edit_params_.vertcost);
    cost("Subcost", edit_params_.subcost);
    ImGui::SliderInt("max granularity", &edit_params_.max_granularity, 2, 64);
    int axis = int(edit_params_.axis);
    ImGui::RadioButton("alternate axes", &axis, int(AxisRule::alternate));
    ImGui::SameLine();
    ImGui::RadioButton("axis by cost", &axis, int(AxisRule::cost));
    edit_params_.axis = AxisRule(axis);
    ImGui::InputText("memory budget", budget_text_, sizeof budget_text_);
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip(
          "bytes of structure, suffix K, M or G; a voxel that would exceed it "
          "stays a leaf");
    if (ImGui::Button("Apply (rebuild)")) apply_structure();
  }

  // The edited structure and parameters replace the current ones: a new structure.
  void apply_structure() {
    try {
      apply_structure_flag(edit_params_, "--memory-budget", budget_text_);
    } catch (const UsageError& e) {
      set_status(e.what());
      return;
    }
    const std::vector<std::string> names = accelerator_names();
    if (edit_accel_ >= 0 && edit_accel_ < int(names.size()))
      setup_.accel = names[size_t(edit_accel_)];
    setup_.params = edit_params_;
    restart_structure();
  }

  void overlay_controls() {
    bool changed = ImGui::Checkbox("cells", &show_cells_);
    ImGui::SameLine();
    changed |= ImGui::Checkbox("states", &show_states_);
    ImGui::SameLine();
    if (ImGui::Checkbox("walk", &show_walk_)) walk_changed();
    int by_axis = colour_by_axis_ ? 1 : 0;
    ImGui::TextUnformatted("cell colour");
    ImGui::SameLine();
    changed |= ImGui::RadioButton("depth", &by_axis, 0);
    ImGui::SameLine();
    changed |= ImGui::RadioButton("axis", &by_axis, 1);
    colour_by_axis_ = by_axis == 1;
    if (changed) overlays_dirty_ = true;
    heat_controls();
  }

  void heat_controls() {
    int heat = int(heat_);
    if (ImGui::Combo("heatmap", &heat, kHeatNames, IM_ARRAYSIZE(kHeatNames))) {
      heat_ = HeatKind(heat);
      heat_dirty_ = true;
    }
    if (heat_ == HeatKind::none) return;
    heat_dirty_ |= ImGui::Checkbox("auto range", &heat_auto_);
    if (ImGui::DragFloatRange2("range", &heat_lo_, &heat_hi_, 0.1f, 0.0f, 1e6f)) {
      heat_auto_ = false;
      heat_dirty_ = true;
    }
    ImGui::Text("max %.2f per sample", heat_max_);
    heat_legend();
    const ImGuiIO& io = ImGui::GetIO();
    if (view_.contains(io.MousePos) && frame_.width > 0 && !heat_values_.empty()) {
      const int x = int((io.MousePos.x - view_.x) / view_.w * frame_.width);
      const int y = int((io.MousePos.y - view_.y) / view_.h * frame_.height);
      const size_t i = size_t(std::clamp(y, 0, frame_.height - 1)) * size_t(frame_.width) +
                       size_t(std::clamp(x, 0, frame_.width - 1));
      if (i < heat_values_.size())
        ImGui::Text("under the cursor (%d, %d): %.2f", x, y, heat_values_[i]);
    }
  }

  // The turbo bar from the range's low to its high end.
  void heat_legend() {
    constexpr int kSteps = 32;
    constexpr float kHeight = 10.0f;
    ImDrawList* draw = ImGui::GetWindowDrawList();
    const ImVec2 at = ImGui::GetCursorScreenPos();
    const float width = ImGui::GetContentRegionAvail().x;
    for (int i = 0; i < kSteps; ++i) {
      const std::array<uint8_t, 3> c0 = turbo(float(i) / kSteps), c1 = turbo(float(i + 1) / kSteps);
      const ImU32 left = IM_COL32(c0[0], c0[1], c0[2], 255);
      const ImU32 right = IM_COL32(c1[0], c1[1], c1[2], 255);
      draw->AddRectFilledMultiColor(ImVec2(at.x + width * i / kSteps, at.y),
                                    ImVec2(at.x + width * (i + 1) / kSteps, at.y + kHeight), left,
                                    right, right, left);
    }
    ImGui::Dummy(ImVec2(width, kHeight));
    ImGui::Text("%.3g", heat_lo_);
    ImGui::SameLine(std::max(width - 60.0f, 40.0f));
    ImGui::Text("%.3g", heat_hi_);
  }

  void camera_controls() {
    ImGui::InputText("##camera", camera_text_, sizeof camera_text_);
    ImGui::SameLine();
    if (ImGui::Button("set")) {
      try {
        const Camera camera = parse_camera(camera_text_);
        pivot_ = camera.target;
        move_camera(camera);
        set_status("");
      } catch (const UsageError& e) {
        set_status(std::string("camera: ") + e.what());
      }
    }
    ImGui::Checkbox("fly (W/A/S/D)", &fly_);
    ImGui::TextDisabled("drag: orbit  shift/middle drag: pan  wheel: dolly");
    ImGui::TextDisabled("double-click: pivot  click: walk  F: frame  R: reset");
  }

  void scene_controls() {
    ImGui::InputText("##scene", scene_path_, sizeof scene_path_);
    ImGui::SameLine();
    if (ImGui::Button("Open")) open_scene(scene_path_);
    if (const std::optional<std::string> loading = loader_.pending())
      ImGui::TextWrapped("loading %s...", loading->c_str());
  }

  // Loads on the loader's thread: a huge file does not freeze the window, and a newer open
  // supersedes this one.
  void open_scene(const std::string& spec) {
    copy_text(scene_path_, sizeof scene_path_, spec);
    loader_.load(spec);
  }

  // A finished load: the new scene framed, or its error in the status line while the
  // previous scene stays. Framing needs the viewport's aspect: taken once laid out.
  void take_loaded_scene() {
    if (setup_.width == 0) return;
    std::optional<SceneLoader::Result> loaded = loader_.take();
    if (!loaded) return;
    if (!loaded->scene) {
      set_status(loaded->error);  // the previous scene stays
      return;
    }
    scene_ = std::move(loaded->scene);
    setup_.scene = scene_;
    start_camera_ = frame_box(scene_->bounds(), float(setup_.width) / float(setup_.height));
    pivot_ = start_camera_->target;
    setup_.camera = *start_camera_;
    copy_text(camera_text_, sizeof camera_text_, to_string(setup_.camera));
    restart_structure();
    set_status("");
  }

  void bottom_panel() {
    place(0, view_.h, view_.w, std::max(ImGui::GetIO().DisplaySize.y - view_.h, 1.0f));
    ImGui::Begin("statistics and inspector", nullptr, kPanelFlags);
    if (ImGui::BeginTabBar("tabs")) {
      if (ImGui::BeginTabItem("walk")) {
        inspector();
        ImGui::EndTabItem();
      }
      if (ImGui::BeginTabItem("statistics")) {
        statistics();
        ImGui::EndTabItem();
      }
      if (ImGui::BeginTabItem("states")) {
        states_panel();
        ImGui::EndTabItem();
      }
      ImGui::EndTabBar();
    }
    ImGui::End();
  }

  void statistics() {
    const StructureStats& s = frame_.structure;
    ImGui::Text("%s, %zu triangles, pass %d, %d spp, %.3g rays/s, %llu rays", setup_.accel.c_str(),
                scene_->triangle_count(), frame_.pass, frame_.spp, frame_.rays_per_second,
                (unsigned long long)frame_.rays);
    ImGui::Text("nodes %s  subdivided %s  leaves %s  states %s  memory %.1f MB (budget %s)",
                optional_figure(s.nodes).c_str(), optional_figure(s.voxels_subdivided).c_str(),
                optional_figure(s.leaves).c_str(), optional_figure(s.traversal_states).c_str(),
                double(s.memory_bytes) / 1e6, byte_text(setup_.params.memory_budget).c_str());
    if (s.voxels_over_budget > 0)
      ImGui::TextColored(kWarning, "%llu voxels over budget: left as leaves (raise the budget)",
                         (unsigned long long)s.voxels_over_budget);
    else
      ImGui::TextDisabled("voxels over budget: 0");
    ImGui::Text("overlays show %zu nodes built (refreshed every %.1f s while it grows)",
                nodes_built_, kOverlayInterval);
    if (!frame_.error.empty()) ImGui::TextColored(kWarning, "%s", frame_.error.c_str());
    for (const LineSet& set : structure_lines_)
      for (size_t i = 0; i < std::min<size_t>(set.legend.size(), 8); ++i) {
        const glm::vec4 c = set.legend[i].color;
        ImGui::TextColored(ImVec4(c.r, c.g, c.b, 1.0f), "%s", set.legend[i].label.c_str());
      }
  }

  void states_panel() {
    if (!ImGui::BeginTable("states", 5, ImGuiTableFlags_RowBg | ImGuiTableFlags_ScrollY)) return;
    ImGui::TableSetupColumn("state");
    ImGui::TableSetupColumn("axis");
    ImGui::TableSetupColumn("G");
    ImGui::TableSetupColumn("voxels");
    ImGui::TableSetupColumn("rays that used it");
    ImGui::TableHeadersRow();
    for (const StateRow& row : states_) {
      ImGui::TableNextRow();
      ImGui::TableNextColumn();
      ImGui::Text("%u", row.state);
      ImGui::TableNextColumn();
      ImGui::Text("%c", "xyz"[row.axis % 3]);
      ImGui::TableNextColumn();
      ImGui::Text("%llu", (unsigned long long)row.absolute_granularity);
      ImGui::TableNextColumn();
      ImGui::Text("%llu", (unsigned long long)row.voxels);
      ImGui::TableNextColumn();
      ImGui::Text("%llu", (unsigned long long)row.rays);
    }
    ImGui::EndTable();
  }

  void inspector() {
    if (!walk_) {
      ImGui::TextUnformatted("Click the image to inspect that pixel's ray walk.");
      return;
    }
    const int last = std::max(int(walk_->cells.size()) - 1, 0);
    const int before = walk_cell_;
    ImGui::Text("pixel %d,%d  hit %d  t %.6g  %zu cells", walk_pixel_[0], walk_pixel_[1],
                walk_->hit.id, double(walk_->hit.t), walk_->cells.size());
    if (ImGui::Button("first")) walk_cell_ = 0;
    ImGui::SameLine();
    if (ImGui::Button("prev")) walk_cell_ = std::max(walk_cell_ - 1, 0);
    ImGui::SameLine();
    if (ImGui::Button("next")) walk_cell_ = std::min(walk_cell_ + 1, last);
    ImGui::SameLine();
    if (ImGui::Button("last")) walk_cell_ = last;
    ImGui::SameLine();
    ImGui::SetNextItemWidth(-1);
    ImGui::SliderInt("##cell", &walk_cell_, 0, last);
    if (walk_cell_ != before) walk_changed();
    const float half = ImGui::GetContentRegionAvail().x * 0.6f;
    ImGui::BeginChild("cells", ImVec2(half, 0));
    walk_table();
    ImGui::EndChild();
    ImGui::SameLine();
    ImGui::BeginChild("cost", ImVec2(0, 0));
    cost_breakdown();
    ImGui::EndChild();
  }

  void walk_table() {
    const ImGuiTableFlags flags = ImGuiTableFlags_RowBg | ImGuiTableFlags_ScrollY |
                                  ImGuiTableFlags_ScrollX | ImGuiTableFlags_Resizable |
                                  ImGuiTableFlags_SizingFixedFit;
    if (!ImGui::BeginTable("walk", 9, flags)) return;
    for (const char* name :
         {"#", "depth", "entered", "climbed", "descents", "tests", "rejected", "hit", "voxel"})
      ImGui::TableSetupColumn(name);
    ImGui::TableSetupScrollFreeze(1, 1);
    ImGui::TableHeadersRow();
    ImGuiListClipper clipper;
    clipper.Begin(int(walk_->cells.size()));
    while (clipper.Step())
      for (int i = clipper.DisplayStart; i < clipper.DisplayEnd; ++i) walk_row(i);
    ImGui::EndTable();
  }

  void walk_row(int i) {
    const WalkCell& c = walk_->cells[size_t(i)];
    ImGui::TableNextRow();
    ImGui::TableNextColumn();
    if (ImGui::Selectable(std::to_string(i).c_str(), i == walk_cell_,
                          ImGuiSelectableFlags_SpanAllColumns)) {
      walk_cell_ = i;
      walk_changed();
    }
    ImGui::TableNextColumn();
    ImGui::Text("%u", c.depth);
    ImGui::TableNextColumn();
    ImGui::TextUnformatted(c.entered_axis < 0 ? "start"
                                              : std::string(1, "xyz"[c.entered_axis % 3]).c_str());
    ImGui::TableNextColumn();
    ImGui::Text("%u", c.climbed);
    ImGui::TableNextColumn();
    ImGui::TextUnformatted(descents_text(c).c_str());
    ImGui::TableNextColumn();
    ImGui::Text("%u", c.tests);
    ImGui::TableNextColumn();
    ImGui::Text("%u", c.rejections);
    ImGui::TableNextColumn();
    ImGui::Text("%d", c.hit);
    ImGui::TableNextColumn();
    ImGui::Text("%u", c.voxel);
  }

  // The §6 cost model for the inspected cell's parent voxel, as the build evaluated it
  // (Grid1D::cost_report), beside what this ray did there.
  void cost_breakdown() {
    if (!cost_) {
      ImGui::TextWrapped("Cell %d: no parent voxel (the root is a leaf) or no 1D grid.",
                         walk_cell_);
      return;
    }
    const VoxelCostReport& r = *cost_;
    const VoxelFigures& f = r.figures;
    ImGui::Text("parent voxel %u, depth %u: cut on %c into g = %d", r.voxel, r.depth,
                "xyz"[std::max(r.axis, 0) % 3], r.granularity);
    ImGui::Text("N = %.0f, extent %.3g x %.3g x %.3g, mean size %.3g %.3g %.3g", f.triangles,
                f.extent[0], f.extent[1], f.extent[2], f.mean_size[0], f.mean_size[1],
                f.mean_size[2]);
    ImGui::Text("estimated rays %.4g, subdivision cost Subcost*N = %.4g", f.rays,
                r.subdivision_cost);
    for (const AxisPlan& plan : r.plans)
      ImGui::Text("axis %c: best g %d, %.4g per ray vs %.4g uncut: %s", "xyz"[plan.axis],
                  plan.granularity > 1 ? plan.granularity : plan.cost.spanned_cells,
                  plan.cost.total, plan.no_split, plan.granularity > 1 ? "cut pays" : "keep");
    ImGui::TextUnformatted("g     int    trav   rep    ver    total  (per ray, chosen axis)");
    for (const VoxelCostReport::Alternative& alt : r.alternatives) {
      if (alt.axis != r.axis) continue;
      const CutCost& c = alt.cost;
      ImGui::Text("%-3d%s %-6.3g %-6.3g %-6.3g %-6.3g %-6.3g", alt.granularity,
                  alt.granularity == r.granularity ? "*" : " ", c.int_cost, c.trav_cost, c.rep_cost,
                  c.ver_cost, c.total);
    }
    ImGui::Text("this ray here: %d cells, %llu tests, %llu mailbox rejections", ray_here_.cells,
                (unsigned long long)ray_here_.tests, (unsigned long long)ray_here_.rejections);
  }

  const ViewJob& job_;
  gl::Window window_;  // first: the GL context outlives every GL object below
  gl::ImGuiRenderer imgui_renderer_;
  gl::FrameRenderer frame_renderer_;
  Target target_;
  std::shared_ptr<const Scene> scene_;
  ProgressiveRenderer renderer_;  // its destructor stops the workers
  SceneLoader loader_;            // its destructor waits for a load in progress
  std::vector<ScriptStep> steps_;
  size_t next_step_ = 0;

  ViewSetup setup_;
  uint64_t restarts_ = 0;
  std::map<uint64_t, Camera> cameras_;  // the camera of each generation, for its frames
  std::optional<Camera> start_camera_;
  glm::vec3 pivot_{0.0f};
  ProgressiveFrame frame_;
  Camera frame_camera_;
  std::vector<float> distances_;
  Rect view_;
  float scale_ = 1.0f;
  int max_viewport_side_ = kMaxViewportSide;

  // Editing copies: applied on "Apply".
  int edit_accel_ = 0;
  AccelParams edit_params_;

  bool show_cells_ = false, show_states_ = false, show_walk_ = true, colour_by_axis_ = false;
  HeatKind heat_ = HeatKind::none;
  bool heat_auto_ = true, heat_dirty_ = true;
  float heat_lo_ = 0.0f, heat_hi_ = 1.0f, heat_max_ = 0.0f;
  std::vector<float> heat_values_;
  std::vector<uint8_t> heat_rgba_;

  std::vector<LineSet> structure_lines_;
  std::vector<StateRow> states_;
  size_t nodes_built_ = 0;
  Clock::time_point overlay_time_{};
  uint64_t overlay_nodes_ = 0;
  bool overlays_dirty_ = true, cost_dirty_ = false;

  std::optional<Walk> walk_;
  std::array<int, 2> walk_pixel_{0, 0}, walk_size_{0, 0};
  Camera walk_camera_;
  int walk_cell_ = 0;
  LineSet walk_lines_;
  std::optional<VoxelCostReport> cost_;  // of the inspected cell's parent voxel
  RayInVoxel ray_here_;

  int dragging_ = 0;
  bool drag_active_ = false, drag_moved_ = false, skip_release_ = false, fly_ = false;
  char camera_text_[512] = {};
  char scene_path_[1024] = {};
  char budget_text_[32] = {};
  std::string status_;

  int frames_done_ = 0, click_frame_ = 0;
  bool full_pass_current_ = false, click_done_ = false;
};

// `text` without leading and trailing blanks (a Windows line end among them).
std::string trimmed(const std::string& text) {
  const size_t first = text.find_first_not_of(" \t\r");
  if (first == std::string::npos) return "";
  return text.substr(first, text.find_last_not_of(" \t\r") - first + 1);
}

// The blank-separated words of a script line's part.
std::vector<std::string> split_words(const std::string& text) {
  std::vector<std::string> words;
  std::istringstream in(text);
  for (std::string word; in >> word;) words.push_back(word);
  return words;
}

// An integer that is the whole word.
std::optional<int> whole_int(const std::string& word) {
  int value = 0;
  const auto [end, error] = std::from_chars(word.data(), word.data() + word.size(), value);
  if (error != std::errc() || end != word.data() + word.size()) return std::nullopt;
  return value;
}

// WxH for `resize`: 0x0 (minimised) or each side 1..kMaxImageSide.
std::optional<std::array<int, 2>> window_size(const std::string& word) {
  const size_t x = word.find('x');
  if (x == std::string::npos) return std::nullopt;
  const std::optional<int> w = whole_int(word.substr(0, x)), h = whole_int(word.substr(x + 1));
  if (!w || !h || (*w == 0) != (*h == 0) || *w < 0 || *h < 0 || *w > kMaxImageSide ||
      *h > kMaxImageSide)
    return std::nullopt;
  return std::array<int, 2>{*w, *h};
}

// One step from "ACTION ARGS" (trimmed); throws UsageError describing what is wrong.
ScriptStep parse_action(const std::string& action) {
  const std::vector<std::string> words = split_words(action);
  ScriptStep step;
  const std::string verb = words.empty() ? "" : words[0];
  if (verb == "resize" && words.size() == 2) {
    const std::optional<std::array<int, 2>> size = window_size(words[1]);
    if (!size)
      throw UsageError("resize '" + words[1] + "': expected WxH, 0x0 or sides 1.." +
                       std::to_string(kMaxImageSide));
    step.action = ScriptStep::Action::resize, step.size = *size;
  } else if (verb == "open" && words.size() >= 2) {
    step.action = ScriptStep::Action::open;
    step.name = trimmed(action.substr(verb.size()));  // a path may hold blanks
  } else if (verb == "set" && words.size() == 3) {
    step.action = ScriptStep::Action::set, step.name = words[1], step.value = words[2];
    const std::vector<std::string> names = accelerator_names();
    if (step.name != "accel") {
      AccelParams checked;  // the value is checked as the command line checks it
      apply_structure_flag(checked, "--" + step.name, step.value);
    } else if (std::find(names.begin(), names.end(), step.value) == names.end()) {
      throw UsageError("set accel '" + step.value + "': unknown structure");
    }
  } else if (verb == "close" && words.size() == 1) {
    step.action = ScriptStep::Action::close;
  } else {
    throw UsageError("'" + action + "': expected resize WxH, open SCENE, set NAME VALUE or close");
  }
  return step;
}

void check_view_usage(const ViewJob& job) {
  make_accelerator(job.accel, job.params);  // UsageError for an unknown structure
  if (!job.walk_out.empty() && !job.click) throw UsageError("view: --walk-out needs --click X,Y");
  if (!job.walk_out.empty() && job.accel != "grid1d")
    throw UsageError("view: --walk-out needs --accel grid1d ('" + job.accel + "' has no cells)");
}

}  // namespace

std::array<double, 2> parse_click(const std::string& text) {
  const size_t comma = text.find(',');
  const auto part = [&](const std::string& word) {
    double value = 0.0;
    const auto [end, error] = std::from_chars(word.data(), word.data() + word.size(), value);
    if (comma == std::string::npos || word.empty() || error != std::errc() ||
        end != word.data() + word.size() || !(value >= 0.0 && value <= 1.0))
      throw UsageError("--click '" + text + "': expected X,Y, fractions 0..1 of the viewport");
    return value;
  };
  return {part(text.substr(0, comma)),
          part(comma == std::string::npos ? "" : text.substr(comma + 1))};
}

std::vector<ScriptStep> parse_script(const std::string& text, const std::string& path) {
  std::vector<ScriptStep> steps;
  std::istringstream lines(text);
  int number = 0;
  for (std::string line; std::getline(lines, line);) {
    ++number;
    line = trimmed(line);
    if (line.empty() || line[0] == '#') continue;
    const std::string where = path + ":" + std::to_string(number) + ": ";
    const size_t colon = line.find(':');
    const std::vector<std::string> head =
        split_words(colon == std::string::npos ? "" : line.substr(0, colon));
    const std::optional<int> frame = head.size() == 2 ? whole_int(head[1]) : std::nullopt;
    if (head.size() != 2 || head[0] != "frame" || !frame || *frame < 1)
      throw InputError(where + "expected 'frame N: ACTION' with N >= 1");
    try {
      steps.push_back(parse_action(trimmed(line.substr(colon + 1))));
    } catch (const UsageError& e) {
      throw InputError(where + e.what());
    }
    steps.back().frame = *frame;
  }
  std::stable_sort(steps.begin(), steps.end(),
                   [](const ScriptStep& a, const ScriptStep& b) { return a.frame < b.frame; });
  return steps;
}

void run_view(const ViewJob& job) {
  check_view_usage(job);
  std::vector<ScriptStep> steps;
  if (!job.script.empty()) {
    const std::vector<char> text = read_file(job.script);
    steps = parse_script(std::string(text.begin(), text.end()), job.script);
  }
  // The scene is read before the window opens, so a bad file is one line and exit 1.
  auto scene =
      std::make_shared<const Scene>(load_scene(job.scene.empty() ? kDefaultScene : job.scene));
  Viewer viewer(job, std::move(scene), std::move(steps));
  viewer.run();
}

}  // namespace gs::app
