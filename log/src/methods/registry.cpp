// The table of culling methods (method.hpp): one line per method, in the order of the
// enum; each method's definition is in its own file of this folder.
#include <cassert>

#include "method_def.hpp"

namespace logrid {
namespace detail {

const MethodDef& logZfarMethod();
const MethodDef& bogMethod();
const MethodDef& hzbMethod();
const MethodDef& pqMethod();
const MethodDef& vfcMethod();
const MethodDef& hwqMethod();
const MethodDef& chcMethod();
const MethodDef& statMethod();
const MethodDef& nohcMethod();
const MethodDef& logHwqMethod();
const MethodDef& ddoMethod();
const MethodDef& ddoLogMethod();
const MethodDef& autoMethod();

namespace {

const std::vector<const MethodDef*>& definitions() {
  static const std::vector<const MethodDef*> table = [] {
    std::vector<const MethodDef*> t = {
        &logStateMethod(), &logZfarMethod(), &bogMethod(),    &hzbMethod(),  &pqMethod(),
        &vfcMethod(),      &hwqMethod(),     &chcMethod(),    &statMethod(), &nohcMethod(),
        &logHwqMethod(),   &ddoMethod(),     &ddoLogMethod(), &autoMethod(),
    };
    for (std::size_t i = 0; i < t.size(); ++i) {
      assert(std::size_t(t[i]->info.method) == i && "registry: a method out of enum order");
    }
    return t;
  }();
  return table;
}

}  // namespace

const MethodDef& methodDef(Method method) {
  const auto& table = definitions();
  assert(std::size_t(method) < table.size() && "methodDef: unknown method");
  return *table[std::size_t(method)];
}

}  // namespace detail

const std::vector<MethodInfo>& methodTable() {
  static const std::vector<MethodInfo> table = [] {
    std::vector<MethodInfo> t;
    for (const detail::MethodDef* d : detail::definitions()) t.push_back(d->info);
    return t;
  }();
  return table;
}

const MethodInfo& methodInfo(Method method) { return detail::methodDef(method).info; }

const char* toString(Method method) {
  const auto& table = methodTable();
  return std::size_t(method) < table.size() ? table[std::size_t(method)].name : "?";
}

std::optional<Method> parseMethod(const std::string& name) {
  for (const MethodInfo& m : methodTable()) {
    if (name == m.name) return m.method;
  }
  return std::nullopt;
}

std::string methodNames() {
  std::string out;
  for (const MethodInfo& m : methodTable()) {
    if (!out.empty()) out += ", ";
    out += m.name;
  }
  return out;
}

}  // namespace logrid
