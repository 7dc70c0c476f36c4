// A linked GLSL program, owned (shared by the GL depth sources and the renderer). Compile and link
// errors throw logrid::Error with the driver's log and the name given.
#pragma once

#include <cstdint>
#include <initializer_list>
#include <string>

namespace logrid::zread {

class Program {
 public:
  Program(const std::string& name, const char* vertex_source, const char* fragment_source);
  // A compute program.
  Program(const std::string& name, const char* compute_source);
  ~Program();
  Program(const Program&) = delete;
  Program& operator=(const Program&) = delete;

  std::uint32_t handle() const { return program_; }
  void use() const;
  // The location of a uniform; throws if the program has no such active uniform.
  std::int32_t uniform(const char* uniform_name) const;

 private:
  void link(std::initializer_list<std::uint32_t> shaders);  // takes and deletes the shaders
  std::string name_;
  std::uint32_t program_ = 0;
};

}  // namespace logrid::zread
