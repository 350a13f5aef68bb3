// A linked GLSL program made from two of the embedded shaders (app/gl/shaders.h, generated
// from shaders/). Needs a current GL 3.3 context with glad loaded.
#pragma once
#include <string>

namespace gs::gl {

class Program {
 public:
  // Throws InputError("OpenGL: shader NAME: LOG") when a stage does not compile or link:
  // a driver that cannot take our GLSL is a failed run, not a crash.
  Program(const std::string& name, const char* vertex_source, const char* fragment_source);
  ~Program();
  Program(const Program&) = delete;
  Program& operator=(const Program&) = delete;

  unsigned id() const { return id_; }
  int uniform(const char* name) const;

 private:
  unsigned id_ = 0;
};

}  // namespace gs::gl
