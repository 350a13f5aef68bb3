#include "app/gl/program.h"

#include <glad/gl.h>

#include <vector>

#include "core/base/error.h"

namespace gs::gl {

namespace {

std::string info_log(GLuint object, bool is_program) {
  GLint length = 0;
  if (is_program)
    glGetProgramiv(object, GL_INFO_LOG_LENGTH, &length);
  else
    glGetShaderiv(object, GL_INFO_LOG_LENGTH, &length);
  std::vector<char> log(size_t(std::max(length, 1)), '\0');
  if (is_program)
    glGetProgramInfoLog(object, GLsizei(log.size()), nullptr, log.data());
  else
    glGetShaderInfoLog(object, GLsizei(log.size()), nullptr, log.data());
  return log.data();
}

GLuint compile(const std::string& name, GLenum stage, const char* source) {
  const GLuint shader = glCreateShader(stage);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = GL_FALSE;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    const std::string log = info_log(shader, false);
    glDeleteShader(shader);
    throw InputError("OpenGL: shader " + name + ": " + log);
  }
  return shader;
}

}  // namespace

Program::Program(const std::string& name, const char* vertex_source, const char* fragment_source) {
  const GLuint vertex = compile(name + ".vert", GL_VERTEX_SHADER, vertex_source);
  GLuint fragment = 0;
  try {
    fragment = compile(name + ".frag", GL_FRAGMENT_SHADER, fragment_source);
  } catch (...) {
    glDeleteShader(vertex);
    throw;
  }
  id_ = glCreateProgram();
  glAttachShader(id_, vertex);
  glAttachShader(id_, fragment);
  glLinkProgram(id_);
  glDeleteShader(vertex);  // the program keeps them alive while attached
  glDeleteShader(fragment);
  GLint ok = GL_FALSE;
  glGetProgramiv(id_, GL_LINK_STATUS, &ok);
  if (!ok) {
    const std::string log = info_log(id_, true);
    glDeleteProgram(id_);
    throw InputError("OpenGL: shader " + name + ": " + log);
  }
}

Program::~Program() { glDeleteProgram(id_); }

int Program::uniform(const char* name) const { return glGetUniformLocation(id_, name); }

}  // namespace gs::gl
