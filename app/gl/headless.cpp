#include "app/gl/headless.h"

// glad first: it claims the GL header guard, so osmesa.h's <GL/gl.h> adds nothing that
// could bypass the loader.
#include <glad/gl.h>
// clang-format off
#include <GL/osmesa.h>
// clang-format on

#include <dlfcn.h>

#include <string>

#include "core/base/error.h"

namespace gs::gl {

namespace {

[[noreturn]] void no_context() {
  throw InputError("OSMesa: could not create an OpenGL 3.3 context");
}

// libOSMesa, opened when the first headless context is made, not linked: it brings Mesa's
// llvmpipe and with it LLVM, whose loading and static initialisation cost every start of the
// program about 60 ms and 3,200 page faults, whatever the command (measured on `gridscope
// --version`: 0.06 s with OSMesa linked). Only `shot` and the plots need it. Kept open for
// the life of the process, as a linked library would be.
struct OsMesa {
  decltype(&OSMesaCreateContextAttribs) create = nullptr;
  decltype(&OSMesaMakeCurrent) make_current = nullptr;
  decltype(&OSMesaDestroyContext) destroy = nullptr;
  decltype(&OSMesaGetProcAddress) get_proc = nullptr;
};

template <class Function>
void resolve(void* library, const char* name, Function& function) {
  function = reinterpret_cast<Function>(dlsym(library, name));
  if (!function)
    throw InputError(std::string("OSMesa: ") + GRIDSCOPE_OSMESA_LIBRARY + " has no " + name);
}

const OsMesa& osmesa() {
  static const OsMesa loaded = [] {
    void* library = dlopen(GRIDSCOPE_OSMESA_LIBRARY, RTLD_NOW | RTLD_LOCAL);
    if (!library) {
      const char* why = dlerror();
      throw InputError(std::string("OSMesa: could not load ") + GRIDSCOPE_OSMESA_LIBRARY + ": " +
                       (why ? why : "unknown error"));
    }
    OsMesa functions;
    resolve(library, "OSMesaCreateContextAttribs", functions.create);
    resolve(library, "OSMesaMakeCurrent", functions.make_current);
    resolve(library, "OSMesaDestroyContext", functions.destroy);
    resolve(library, "OSMesaGetProcAddress", functions.get_proc);
    return functions;
  }();
  return loaded;
}

GLADapiproc osmesa_proc(const char* name) {
  return reinterpret_cast<GLADapiproc>(osmesa().get_proc(name));
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
  const OsMesa& mesa = osmesa();
  OSMesaContext context = mesa.create(attributes, nullptr);
  if (!context) no_context();
  context_ = context;
  if (!mesa.make_current(context, buffer_.data(), GL_UNSIGNED_BYTE, width, height)) {
    mesa.destroy(context);
    context_ = nullptr;
    no_context();
  }
  const int version = gladLoadGL(osmesa_proc);
  if (version == 0 || GLAD_VERSION_MAJOR(version) * 10 + GLAD_VERSION_MINOR(version) < 33) {
    mesa.destroy(context);
    context_ = nullptr;
    no_context();
  }
}

HeadlessContext::~HeadlessContext() {
  if (context_) osmesa().destroy(static_cast<OSMesaContext>(context_));
}

}  // namespace gs::gl
