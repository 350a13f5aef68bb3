// An offscreen OpenGL 3.3 core context from OSMesa (Mesa's software rasteriser): no display,
// no GPU. `gridscope shot` draws into it what the viewer draws into its window.
#pragma once
#include <cstdint>
#include <vector>

namespace gs::gl {

class HeadlessContext {
 public:
  // A width x height RGBA8 framebuffer with a 24-bit depth buffer, made current and with
  // glad loaded through OSMesaGetProcAddress. Throws InputError("OSMesa: could not create
  // an OpenGL 3.3 context") when Mesa cannot give one (exit status 1, docs/design.md §3).
  HeadlessContext(int width, int height);
  ~HeadlessContext();
  HeadlessContext(const HeadlessContext&) = delete;
  HeadlessContext& operator=(const HeadlessContext&) = delete;

  int width() const { return width_; }
  int height() const { return height_; }

 private:
  void* context_ = nullptr;      // OSMesaContext, kept opaque so callers need no osmesa.h
  std::vector<uint8_t> buffer_;  // OSMesa renders straight into this memory
  int width_ = 0;
  int height_ = 0;
};

}  // namespace gs::gl
