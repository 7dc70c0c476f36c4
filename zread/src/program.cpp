#include "logrid/zread/program.hpp"

#include <epoxy/gl.h>

#include <cassert>
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

Result<GLuint> compileStage(const std::string& name, GLenum stage, const char* source) {
  const GLuint shader = glCreateShader(stage);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[2048] = {};
    glGetShaderInfoLog(shader, sizeof log, nullptr, log);
    glDeleteShader(shader);
    return Status(ErrorCode::Runtime, "program '" + name + "': " + stageName(stage) +
                                          " shader does not compile: " + log);
  }
  return shader;
}

}  // namespace

Result<std::unique_ptr<Program>> Program::create(const std::string& name, const char* vertex_source,
                                                 const char* fragment_source) {
  std::unique_ptr<Program> program(new Program(name));
  if (Status built = program->build(vertex_source, fragment_source); !built) return built;
  return program;
}

Result<std::unique_ptr<Program>> Program::create(const std::string& name,
                                                 const char* compute_source) {
  std::unique_ptr<Program> program(new Program(name));
  if (Status built = program->build(compute_source); !built) return built;
  return program;
}

Status Program::build(const char* vertex_source, const char* fragment_source) {
  const Result<GLuint> vs = compileStage(name_, GL_VERTEX_SHADER, vertex_source);
  if (!vs) return vs.status();
  const Result<GLuint> fs = compileStage(name_, GL_FRAGMENT_SHADER, fragment_source);
  if (!fs) {
    glDeleteShader(*vs);
    return fs.status();
  }
  return link({*vs, *fs});
}

Status Program::build(const char* compute_source) {
  const Result<GLuint> cs = compileStage(name_, GL_COMPUTE_SHADER, compute_source);
  if (!cs) return cs.status();
  return link({*cs});
}

Status Program::link(std::initializer_list<std::uint32_t> shaders) {
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
    program_ = 0;
    return Status(ErrorCode::Runtime, "program '" + name_ + "' does not link: " + log);
  }
  return {};
}

Program::~Program() {
  if (program_) glDeleteProgram(program_);
}

void Program::use() const { glUseProgram(program_); }

std::int32_t Program::uniform(const char* uniform_name) const {
  const GLint location = glGetUniformLocation(program_, uniform_name);
  assert(location >= 0 && "Program::uniform: not an active uniform of the program");
  return location;
}

}  // namespace logrid::zread
