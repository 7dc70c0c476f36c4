// A culling method's one definition (method.hpp): what it is and needs (MethodInfo), how
// it tests boxes, its query schedule if it has one, and the checks of its own settings.
// Each method has its file in this folder; registry.cpp lists them. Internal to
// logrid::core.
#pragma once

#include <memory>
#include <string>

#include "logrid/culler.hpp"
#include "logrid/method.hpp"
#include "query_frame.hpp"
#include "testers.hpp"

namespace logrid::detail {

struct MethodDef {
  MethodInfo info;
  // The tester of its boxes: the grid's, the pyramid's, a count, the occluders' map, or
  // none (view-frustum culling; the schedules, whose queries test).
  std::unique_ptr<BoxTester> (*make_tester)(const CullerDesc& desc,
                                            const MethodInfo& info) = nullptr;
  // Traversal::Schedule: the schedule that walks the hierarchy.
  std::unique_ptr<Schedule> (*make_schedule)(const CullerDesc& desc,
                                             const MethodInfo& info) = nullptr;
  // Checks of the settings only this method reads (validateCullerDesc checks the common
  // ones); empty if usable, else a message naming the field. nullptr: none.
  std::string (*validate)(const CullerDesc& desc, const MethodInfo& info) = nullptr;
};

// A definition with its name and one-line description; the rest to fill in.
inline MethodDef methodNamed(Method method, const char* name, const char* description) {
  MethodDef m;
  m.info.method = method;
  m.info.name = name;
  m.info.description = description;
  return m;
}

// A definition built on `base`'s: the same info and functions under its own enum value,
// name and description; the rest to change.
inline MethodDef methodLike(const MethodDef& base, Method method, const char* name,
                            const char* description) {
  MethodDef m = base;
  m.info.method = method;
  m.info.name = name;
  m.info.description = description;
  return m;
}

// The definitions others are built on (each in its own file).
const MethodDef& logStateMethod();

// The definition of a method of the enum (asserts on a value outside it).
const MethodDef& methodDef(Method method);

// The testers most methods take (testers.hpp).
inline std::unique_ptr<BoxTester> lazyGridTester(const CullerDesc& desc, const MethodInfo& info) {
  return makeGridTester(desc, *info.grid, GridRefresh::Lazy);
}
inline std::unique_ptr<BoxTester> noTester(const CullerDesc&, const MethodInfo&) {
  return makeNoTester();
}

// The schedule of a Traversal::Schedule method, and the checks of its settings.
std::unique_ptr<Schedule> makeMethodSchedule(const CullerDesc& desc, const MethodInfo& info);
std::string validateMethodSchedule(const CullerDesc& desc, const MethodInfo& info);

// The methods hwq, chc, stat and nohc: `schedule` over the whole hierarchy, no depth read.
MethodDef queryMethod(Method method, const char* name, const char* description,
                      QuerySchedule schedule);

}  // namespace logrid::detail
