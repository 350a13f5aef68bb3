#include "app/gl/window.h"

// glad first: it claims the GL header guard, and GLFW must not include a GL header itself.
#include <glad/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui/backends/imgui_impl_glfw.h>

#include <utility>

#include "core/base/error.h"

namespace gs::gl {

namespace {

// GLFW reports failures through a callback; keep the last one for the error line.
std::string& last_glfw_error() {
  static std::string text;
  return text;
}

void on_glfw_error(int /*code*/, const char* description) {
  last_glfw_error() = description ? description : "unknown GLFW error";
}

[[noreturn]] void no_window(const std::string& fallback) {
  const std::string& reason = last_glfw_error().empty() ? fallback : last_glfw_error();
  throw InputError("OpenGL: could not open a window (" + reason + ")");
}

GLADapiproc glfw_proc(const char* name) {
  return reinterpret_cast<GLADapiproc>(glfwGetProcAddress(name));
}

}  // namespace

Window::Window(int width, int height, const std::string& title) {
  last_glfw_error().clear();
  glfwSetErrorCallback(on_glfw_error);
  if (!glfwInit()) no_window("GLFW could not start");
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_DEPTH_BITS, 24);
  window_ = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
  // Whatever fails from here, what was made so far is undone before the error line.
  const auto fail = [this](const std::string& fallback) {
    if (window_) glfwDestroyWindow(window_);
    glfwTerminate();
    no_window(fallback);
  };
  if (!window_) fail("no OpenGL 3.3 core context");
  glfwMakeContextCurrent(window_);
  glfwSwapInterval(1);
  // ImGui's GLFW backend installs no refresh callback and uses no window user pointer.
  glfwSetWindowUserPointer(window_, this);
  glfwSetWindowRefreshCallback(window_, [](GLFWwindow* window) {
    static_cast<Window*>(glfwGetWindowUserPointer(window))->refresh_requested_ = true;
  });
  const int version = gladLoadGL(glfw_proc);
  if (version == 0 || GLAD_VERSION_MAJOR(version) * 10 + GLAD_VERSION_MINOR(version) < 33)
    fail("OpenGL 3.3 functions missing");
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;  // the layout is placed in code each frame
  ImGui::GetIO().LogFilename = nullptr;
  if (!ImGui_ImplGlfw_InitForOpenGL(window_, true)) {
    ImGui::DestroyContext();
    fail("ImGui's GLFW backend did not start");
  }
}

Window::~Window() {
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  glfwDestroyWindow(window_);
  glfwTerminate();
}

bool Window::should_close() const { return glfwWindowShouldClose(window_); }

void Window::close() { glfwSetWindowShouldClose(window_, GLFW_TRUE); }

void Window::hide() { glfwHideWindow(window_); }

void Window::wait_events(double seconds) { glfwWaitEventsTimeout(seconds); }

void Window::begin_frame() { ImGui_ImplGlfw_NewFrame(); }

void Window::swap() { glfwSwapBuffers(window_); }

bool Window::take_refresh_request() { return std::exchange(refresh_requested_, false); }

glm::ivec2 Window::framebuffer_size() const {
  glm::ivec2 size(0);
  glfwGetFramebufferSize(window_, &size.x, &size.y);
  return size;
}

bool Window::minimised() const {
  const glm::ivec2 size = framebuffer_size();
  return minimised_by_resize_ || glfwGetWindowAttrib(window_, GLFW_ICONIFIED) || size.x <= 0 ||
         size.y <= 0;
}

void Window::resize(int width, int height) {
  if (width <= 0 || height <= 0) {
    glfwIconifyWindow(window_);
    minimised_by_resize_ = true;
    return;
  }
  if (minimised_by_resize_) glfwRestoreWindow(window_);
  minimised_by_resize_ = false;
  glfwSetWindowSize(window_, width, height);
}

}  // namespace gs::gl
