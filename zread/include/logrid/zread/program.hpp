// A linked GLSL program, owned (shared by the GL depth sources). Compile and link errors
// are ErrorCode::Runtime with the driver's log and the name given, in both forms
// (logrid/error.hpp): create() returns them, the constructors throw them.
#pragma once

#include <cstdint>
#include <initializer_list>
#include <memory>
#include <string>
#include <utility>

#include "logrid/error.hpp"

namespace logrid::zread {

class Program {
 public:
  static Result<std::unique_ptr<Program>> create(const std::string& name, const char* vertex_source,
                                                 const char* fragment_source);
  // A compute program.
  static Result<std::unique_ptr<Program>> create(const std::string& name,
                                                 const char* compute_source);
  Program(const std::string& name, const char* vertex_source, const char* fragment_source);
  Program(const std::string& name, const char* compute_source);
  ~Program();
  Program(const Program&) = delete;
  Program& operator=(const Program&) = delete;

  std::uint32_t handle() const { return program_; }
  void use() const;
  // The location of a uniform of logrid's own shaders: -1 (which GL ignores) if the
  // program has none of that name, asserted against in debug builds; the GL tests find
  // a shader whose uniform went missing by its wrong answers.
  std::int32_t uniform(const char* uniform_name) const;

 private:
  explicit Program(std::string name) : name_(std::move(name)) {}
  Status build(const char* vertex_source, const char* fragment_source);
  Status build(const char* compute_source);
  Status link(std::initializer_list<std::uint32_t> shaders);  // takes and deletes the shaders
  std::string name_;
  std::uint32_t program_ = 0;
};

#if LOGRID_HAS_EXCEPTIONS
inline Program::Program(const std::string& name, const char* vertex_source,
                        const char* fragment_source)
    : Program(name) {
  orThrow(build(vertex_source, fragment_source));
}
inline Program::Program(const std::string& name, const char* compute_source) : Program(name) {
  orThrow(build(compute_source));
}
#endif

}  // namespace logrid::zread
