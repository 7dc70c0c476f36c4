#include "logrid/zread/program.hpp"

#include <epoxy/gl.h>

#include <initializer_list>

#include "logrid/error.hpp"

namespace logrid::zread {
namespace {

const char* stageName(GLenum stage) {
  switch (stage) {
    case GL_VERTEX_SHADER: return "vertex";
    case GL_FRAGMENT_SHADER: return "fragment";
    case GL_COMPUTE_SHADER: return "compute";
  }
  return "?";
}

GLuint compileStage(const std::string& name, GLenum stage, const char* source) {
  const GLuint shader = glCreateShader(stage);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[2048] = {};
    glGetShaderInfoLog(shader, sizeof log, nullptr, log);
    glDeleteShader(shader);
    throw Error(ErrorCode::Runtime,
                "program '" + name + "': " + stageName(stage) + " shader does not compile: " + log);
  }
  return shader;
}

}  // namespace

Program::Program(const std::string& name, const char* vertex_source, const char* fragment_source)
    : name_(name) {
  const GLuint vs = compileStage(name, GL_VERTEX_SHADER, vertex_source);
  GLuint fs = 0;
  try {
    fs = compileStage(name, GL_FRAGMENT_SHADER, fragment_source);
  } catch (...) {
    glDeleteShader(vs);
    throw;
  }
  link({vs, fs});
}

Program::Program(const std::string& name, const char* compute_source) : name_(name) {
  link({compileStage(name, GL_COMPUTE_SHADER, compute_source)});
}

void Program::link(std::initializer_list<std::uint32_t> shaders) {
  program_ = glCreateProgram();
  for (GLuint s : shaders) glAttachShader(program_, s);
  glLinkProgram(program_);
  for (GLuint s : shaders) glDeleteShader(s);
  GLint ok = 0;
  glGetProgramiv(program_, GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[2048] = {};
    glGetProgramInfoLog(program_, sizeof log, nullptr, log);
    glDeleteProgram(program_);
    throw Error(ErrorCode::Runtime, "program '" + name_ + "' does not link: " + log);
  }
}

Program::~Program() {
  if (program_) glDeleteProgram(program_);
}

void Program::use() const { glUseProgram(program_); }

std::int32_t Program::uniform(const char* uniform_name) const {
  const GLint location = glGetUniformLocation(program_, uniform_name);
  if (location < 0) {
    throw Error(ErrorCode::InvalidArgument,
                "program '" + name_ + "' has no active uniform '" + uniform_name + "'");
  }
  return location;
}

}  // namespace logrid::zread
