#include "app/gl/headless.h"

// glad first: it claims the GL header guard, so osmesa.h's <GL/gl.h> adds nothing that
// could bypass the loader.
#include <glad/gl.h>
// clang-format off
#include <GL/osmesa.h>
// clang-format on

#include "core/base/error.h"

namespace gs::gl {

namespace {

[[noreturn]] void no_context() {
  throw InputError("OSMesa: could not create an OpenGL 3.3 context");
}

GLADapiproc osmesa_proc(const char* name) {
  return reinterpret_cast<GLADapiproc>(OSMesaGetProcAddress(name));
}

}  // namespace

HeadlessContext::HeadlessContext(int width, int height)
    : buffer_(size_t(width) * size_t(height) * 4), width_(width), height_(height) {
  const int attributes[] = {OSMESA_FORMAT,
                            OSMESA_RGBA,
                            OSMESA_DEPTH_BITS,
                            24,
                            OSMESA_STENCIL_BITS,
                            0,
                            OSMESA_ACCUM_BITS,
                            0,
                            OSMESA_PROFILE,
                            OSMESA_CORE_PROFILE,
                            OSMESA_CONTEXT_MAJOR_VERSION,
                            3,
                            OSMESA_CONTEXT_MINOR_VERSION,
                            3,
                            0};
  OSMesaContext context = OSMesaCreateContextAttribs(attributes, nullptr);
  if (!context) no_context();
  context_ = context;
  if (!OSMesaMakeCurrent(context, buffer_.data(), GL_UNSIGNED_BYTE, width, height)) {
    OSMesaDestroyContext(context);
    context_ = nullptr;
    no_context();
  }
  const int version = gladLoadGL(osmesa_proc);
  if (version == 0 || GLAD_VERSION_MAJOR(version) * 10 + GLAD_VERSION_MINOR(version) < 33) {
    OSMesaDestroyContext(context);
    context_ = nullptr;
    no_context();
  }
}

HeadlessContext::~HeadlessContext() {
  if (context_) OSMesaDestroyContext(static_cast<OSMesaContext>(context_));
}

}  // namespace gs::gl
