// Draws Dear ImGui's draw data with OpenGL 3.3 core through glad. Debian's imgui 1.86
// OpenGL3 backend finds GL through libGL/GLX by itself and cannot draw under OSMesa
// (docs/design.md §4), so headless shots and the window both use this one renderer and draw the
// panels the same way.
#pragma once
#include <memory>
#include <vector>

struct ImDrawData;

namespace gs::gl {

class Program;

class ImGuiRenderer {
 public:
  // Needs a current GL context and a current ImGui context: uploads that context's font
  // atlas (building it if needed) and registers itself as its renderer backend.
  ImGuiRenderer();
  ~ImGuiRenderer();
  ImGuiRenderer(const ImGuiRenderer&) = delete;
  ImGuiRenderer& operator=(const ImGuiRenderer&) = delete;

  // Draws into the current framebuffer over what is there (straight-alpha blending, one
  // scissor rectangle per command). Leaves blending, scissor and depth test disabled.
  void draw(const ImDrawData* data);

 private:
  void set_state(const ImDrawData* data);

  std::unique_ptr<Program> program_;
  unsigned vao_ = 0, vbo_ = 0, ebo_ = 0, font_ = 0;
  int projection_ = -1, atlas_ = -1;
};

// Dear ImGui's draw data kept as bytes, to tell whether a frame would draw exactly what the
// last one drew. The viewer then leaves the window as it is: under Mesa's CPU renderer and
// Xvfb, drawing and presenting a 1700x1100 window takes about 45 ms of CPU, on the cores the
// progressive renderer traces on. The textures the commands draw are the caller's to watch.
class DrawDataRecord {
 public:
  // True when `data` differs from the one recorded last (or none was); records it.
  bool changed(const ImDrawData* data);

 private:
  std::vector<unsigned char> recorded_, current_;
};

}  // namespace gs::gl
