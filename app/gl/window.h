// The viewer's window: GLFW with an OpenGL 3.3 core context, glad loaded through
// glfwGetProcAddress (docs/design.md §4), and Dear ImGui's GLFW platform backend for input. The
// UI is drawn by our own ImGuiRenderer, never by Debian's OpenGL3 backend, so that the
// window and headless shots draw panels the same way.
#pragma once
#include <glm/vec2.hpp>
#include <string>

struct GLFWwindow;

namespace gs::gl {

class Window {
 public:
  // Opens the window, makes its context current, loads glad, creates an ImGui context and
  // binds the GLFW backend to it. Throws InputError("OpenGL: could not open a window
  // (REASON)") when GLFW cannot start or give a 3.3 core context (exit status 1).
  Window(int width, int height, const std::string& title);
  ~Window();
  Window(const Window&) = delete;
  Window& operator=(const Window&) = delete;

  GLFWwindow* handle() const { return window_; }
  bool should_close() const;
  void close();
  // Takes the window off the screen at once (closing: the workers may take a moment to stop).
  void hide();
  // Handles events, sleeping until one comes (glfwPostEmptyEvent from any thread counts) or
  // `seconds` pass: the frame loop draws only when there may be something new.
  void wait_events(double seconds);
  // Starts the backend's ImGui frame (call before ImGui::NewFrame).
  void begin_frame();
  void swap();
  // True once after the window system asked for the window to be drawn again (it was
  // uncovered, say): what it showed is gone, changed or not.
  bool take_refresh_request();
  // Framebuffer size in pixels (what glViewport and glReadPixels count).
  glm::ivec2 framebuffer_size() const;
  // Nothing to draw into: iconified, a 0x0 framebuffer, or resize(0, 0).
  bool minimised() const;
  // Scripted resizing. 0x0 iconifies the window; without a window manager (Xvfb) nothing
  // iconifies it and X cannot size a window to 0, so the window also counts as minimised
  // until the next resize, which restores it.
  void resize(int width, int height);

 private:
  GLFWwindow* window_ = nullptr;
  bool minimised_by_resize_ = false;
  bool refresh_requested_ = true;  // nothing drawn yet
};

}  // namespace gs::gl
